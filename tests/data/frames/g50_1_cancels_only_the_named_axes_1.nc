G51.1 X0 Y0
G50.1 X0
G01 X10. Y10. F100.
#100=#4022
G50.1 Y0
#101=#4022
M30
(expect: motion1=X10~1e-6,Y-10~1e-6 status=completed)
