#100=ABS[-3]+1
M30
(expect: #100=4 status=completed)
