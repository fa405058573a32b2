#100=ATAN[1]
M30
(expect: #100=45 status=completed)
