G00 X10. Y10.
G68 R90.
G01 X20. F100.
M30
(expect: motion2=X10~1e-6,Y20~1e-6 status=completed)
