G51.1 X5.
G01 X10. Y0 F100.
G03 X10. Y0 I-2. J0
M30
(expect: motion1=X0~1e-6,Y0~1e-6 status=completed)
