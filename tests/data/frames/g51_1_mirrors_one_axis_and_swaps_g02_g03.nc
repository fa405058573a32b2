G00 X0 Y0
G51.1 X0
G01 X10. Y10. F100.
G02 X20. Y0 R10.
G50.1 X0
G00 X0 Y0
M30
(expect: motions=4 motion2=X-10~1e-6,Y10~1e-6 motion3=X-20~1e-6,Y0~1e-6 motion4=X0~1e-6,Y0~1e-6 status=completed)
