#100=LN[1]
M30
(expect: #100=0 status=completed)
