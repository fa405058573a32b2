G66 P9300
G67
G00 X1.
M30
O9300
#100=1
M99
(expect: #100=vacant status=completed)
