#100=-2*3
M30
(expect: #100=-6 status=completed)
