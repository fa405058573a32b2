G51.1 X0
G51 X0 Y0 P2000
G68 X0 Y0 R90.
G01 X10. Y0 F100.
G69 G50 G50.1 X0
M30
(expect: motion1=X0~1e-6,Y20~1e-6 status=completed)
