#100=POW[-2,3]
M30
(expect: #100=-8 status=completed)
