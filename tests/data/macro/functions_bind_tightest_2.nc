#100=2*SQRT[16]+1
M30
(expect: #100=9 status=completed)
