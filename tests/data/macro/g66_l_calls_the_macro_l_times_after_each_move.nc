G66 P9300 L2 A1.
G00 X1.
G00 X2.
G67
M30
O9300
#1=#1+1
#100=#100+#1
M99
(Two moves × two calls, each call starting again from A = 1: 4 × 2 = 8.)
(expect: #100=8 status=completed)
