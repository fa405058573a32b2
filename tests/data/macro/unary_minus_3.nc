#100=-[2+3]
M30
(expect: #100=-5 status=completed)
