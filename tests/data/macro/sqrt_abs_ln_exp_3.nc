#100=ABS[-2.5]
M30
(expect: #100=2.5 status=completed)
