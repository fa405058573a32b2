G16
G68 X0 Y0 R90.
G01 X10. Y0 F100.
M30
(expect: motion1=X0~1e-6,Y10~1e-6 status=completed)
