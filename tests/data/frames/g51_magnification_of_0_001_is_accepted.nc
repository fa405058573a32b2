G51 X0 Y0 P.001
G01 X1000. F100.
M30
(expect: motion1=X1~1e-6 status=completed)
