#100=2+3*4
M30
(expect: #100=14 status=completed)
