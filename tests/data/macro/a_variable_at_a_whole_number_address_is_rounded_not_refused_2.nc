M98 P[9.6]
M30
O0010
#100=10
M99
(M98 P[9.6] calls O0010.)
(expect: #100=10 status=completed)
