G04 X1.
#3001=100
G04 P1000
#100=#3001
M30
(expect: #100=1100 status=completed)
