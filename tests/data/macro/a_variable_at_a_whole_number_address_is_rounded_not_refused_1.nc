G43 H[2.6] Z10.
#100=#4111
G49
M30
(H[2.6] selects H3: #4111 [the H in use] reads 3.)
(expect: #100=3 status=completed)
