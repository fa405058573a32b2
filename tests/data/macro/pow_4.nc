#100=POW[2,-1]
M30
(expect: #100=0.5 status=completed)
