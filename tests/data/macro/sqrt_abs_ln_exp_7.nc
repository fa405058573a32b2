#100=EXP[0]
M30
(expect: #100=1 status=completed)
