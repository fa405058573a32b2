G51.1 X0 Y0
G01 X10. Y0 F100.
G02 X0 Y-10. R10.
M30
(expect: motion1=X-10~1e-6,Y0~1e-6 motion2=X0~1e-6,Y10~1e-6 status=completed)
