G00 Z10.
G68 X0 Y0 R90.
G81 X10. Y0 Z-5. R2. F100.
X20.
G80 G69
M30
(expect: motion2=X0~1e-6,Y10~1e-6,Z10~1e-6 motion3=X0~1e-6,Y10~1e-6,Z2~1e-6 motion4=X0~1e-6,Y10~1e-6,Z-5~1e-6 motion5=X0~1e-6,Y10~1e-6,Z10~1e-6 motion6=X0~1e-6,Y20~1e-6,Z10~1e-6 status=completed)
