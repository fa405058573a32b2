#1=5.
M98 P9002
#101=#1
M30
O9002
#100=#1
#1=9.
M99
(expect: #100=5 #101=9 status=completed)
