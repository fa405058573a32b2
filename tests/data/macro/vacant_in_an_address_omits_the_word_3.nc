G90 G00 X5.
X#1 Y1.
#1=0
X#1
M30
(expect: motion2=X5 motion3=X0 status=completed)
