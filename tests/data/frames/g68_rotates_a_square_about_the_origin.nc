G90 G17 G00 X0 Y0
G68 X0 Y0 R90.
G01 X10. F100.
Y10.
X0
Y0
G69
M30
(Exact at multiples of 90° [no 6e-16 left over].)
(expect: motions=5 motion2=X0~1e-6,Y10~1e-6 motion3=X-10~1e-6,Y10~1e-6 motion4=X-10~1e-6,Y0~1e-6 motion5=X0~1e-6,Y0~1e-6 motion2=X0 status=completed)
