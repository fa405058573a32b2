#100=[2+3]*4
M30
(expect: #100=20 status=completed)
