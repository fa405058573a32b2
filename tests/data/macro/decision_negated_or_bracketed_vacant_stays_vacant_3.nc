#100=ABS[#1]
M30
(But a function of vacant is a number: ABS[#1] = 0.)
(expect: #100=0 status=completed)
