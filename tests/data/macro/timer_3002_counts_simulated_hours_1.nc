#3002=2.
G04 X36.
#100=#3002
M30
(expect: #100=2.01 status=completed)
