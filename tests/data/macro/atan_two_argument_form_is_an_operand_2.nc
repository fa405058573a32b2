#100=10+ATAN[1,1]
M30
(expect: #100=55 status=completed)
