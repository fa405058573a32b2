G51 X0 Y0 P1.5
G01 X10. Y4. F100.
M30
(expect: motion1=X15~1e-6,Y6~1e-6 status=completed)
