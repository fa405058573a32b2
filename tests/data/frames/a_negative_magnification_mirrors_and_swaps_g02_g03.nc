G51 X0 Y0 I-1000 J1000
G01 X10. Y5. F100.
G02 X20. Y5. R5.
M30
(expect: motion1=X-10~1e-6,Y5~1e-6 motion2=X-20~1e-6,Y5~1e-6 status=completed)
