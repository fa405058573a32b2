G20
G68 X0 Y0 R90000
G01 X1. F10.
M30
(expect: motion1=X0~1e-6,Y25.4~1e-6 status=completed)
