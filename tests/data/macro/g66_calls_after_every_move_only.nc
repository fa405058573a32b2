G66 P9300 A1.
G90 G00 X1.
#1=5.
M05
G04 P100
G00 X2.
G67
G00 X3.
M30
O9300
#100=#100+1
#101=#1
G91 G00 Z1.
G90
M99
(Two moves in G66 mode: two calls [not after the G66 block, the assignment, M05, the)
(dwell, the G67 block or the move after G67].)
(The arguments of the G66 block.)
(expect: #100=2 #101=1 status=completed)
