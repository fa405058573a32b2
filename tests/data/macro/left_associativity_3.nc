#100=2*3/6*4
M30
(expect: #100=4 status=completed)
