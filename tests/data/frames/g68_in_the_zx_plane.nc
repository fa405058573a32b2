G18 G68 X0 Z0 R90.
G01 Z10. X0 F100.
M30
(expect: motion1=X10~1e-6,Y0~1e-6,Z0~1e-6 status=completed)
