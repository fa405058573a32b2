G00 X10. Y10. Z0
G51 P500
G01 X20. Z-10. F100.
M30
(expect: motion2=X15~1e-6,Y10~1e-6,Z-5~1e-6 status=completed)
