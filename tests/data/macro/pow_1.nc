#100=POW[2,10]
M30
(expect: #100=1024 status=completed)
