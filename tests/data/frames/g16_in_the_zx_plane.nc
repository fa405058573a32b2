G18 G16
G01 Z10. X90. F100.
M30
(expect: motion1=X10~1e-6,Y0~1e-6,Z0~1e-6 status=completed)
