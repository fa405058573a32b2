M98 P10 L3
#101=1
M30
O0010
#100=#100+1
M99
(expect: #100=3 #101=1 status=completed)
