G00 X1. Y2.
G68 X5. Y5. R45.
G69
M30
(expect: motions=1 status=completed)
