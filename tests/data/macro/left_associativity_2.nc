#100=8/4/2
M30
(expect: #100=1 status=completed)
