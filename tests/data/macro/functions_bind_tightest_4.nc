#100=-ABS[-3]
M30
(expect: #100=-3 status=completed)
