#100=#3001
G04 P2500
#101=#3001
M30
(expect: #100=0 #101=2500 status=completed)
