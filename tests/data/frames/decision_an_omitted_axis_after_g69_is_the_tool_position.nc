G68 X0 Y0 R90.
G01 X10. F100.
G69
X5.
M30
(expect: motion1=X0~1e-6,Y10~1e-6 motion2=X5~1e-6,Y10~1e-6 status=completed)
