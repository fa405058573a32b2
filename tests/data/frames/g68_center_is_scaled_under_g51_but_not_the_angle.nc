G51 X0 Y0 P2000
G68 X5. Y0 R90.
G01 X10. Y0 F100.
G69
G50
M30
(expect: motion1=X10~1e-6,Y10~1e-6 status=completed)
