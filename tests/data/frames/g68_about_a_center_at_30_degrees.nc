G00 X0 Y0
G68 X10. Y5. R30.
G01 X20. Y5. F100.
M30
(expect: motion2=X18.660254037844386~1e-6,Y10~1e-6 status=completed)
