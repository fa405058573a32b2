G51.1 X0 Y0
G50.1
G01 X10. Y10. F100.
M30
(expect: motion1=X10~1e-6,Y10~1e-6 status=completed)
