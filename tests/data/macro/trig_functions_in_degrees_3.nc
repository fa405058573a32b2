#100=TAN[45]
M30
(expect: #100=1 status=completed)
