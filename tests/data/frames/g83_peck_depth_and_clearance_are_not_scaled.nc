G51 X0 Y0 Z0 P2000
G00 Z10.
G83 X10. Y0 Z-10. R2. Q3. F100.
G80
M30
(expect: motion2=X20~1e-6,Y0~1e-6 status=completed)
