M98 P10
M30
O0010
#100=#100+1
M99
(expect: #100=1 status=completed)
