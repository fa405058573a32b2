G00 X10. Y0
G68 X0 Y0 R90.
G91 G01 X5. F100.
G69
X5.
M30
(expect: motion2=X10~1e-6,Y5~1e-6 motion3=X15~1e-6,Y5~1e-6 status=completed)
