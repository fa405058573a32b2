#100=FUP[1.2]
M30
(expect: #100=2 status=completed)
