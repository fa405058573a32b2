G66.1 P9011
M0.5
G67
M30
O9011
#100=#13
M99
(expect: #100=0.5 status=completed)
