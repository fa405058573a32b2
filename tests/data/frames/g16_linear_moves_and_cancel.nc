G16
G01 X10. Y90. F100.
Y180.
G15
X5. Y5.
M30
(expect: motion1=X0~1e-6,Y10~1e-6 motion2=X-10~1e-6,Y0~1e-6 motion3=X5~1e-6,Y5~1e-6 status=completed)
