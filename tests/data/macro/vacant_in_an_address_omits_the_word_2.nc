G90 G00 X5. Y5.
G90 X#1 Y7.
M30
(expect: motions=2 status=completed)
