G43 H[2.6] Z10.
#100=#4111
G49
M30
(H[2.6] selects H3: #4111 [the H in use] reads 3.)
(expect: #100=3)
(skip: tip its only motions are the G43 and G49 blocks, which move the machine by the tool length while the commanded point moves from where it was)
