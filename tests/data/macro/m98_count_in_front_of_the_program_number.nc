M98 P30010
M30
O0010
#100=#100+1
M99
(expect: #100=3 status=completed)
