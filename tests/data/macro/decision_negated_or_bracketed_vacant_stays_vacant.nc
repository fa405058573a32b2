G90 G00 X5.
X-#1 Y1.
M30
(expect: motion2=X5 status=completed)
