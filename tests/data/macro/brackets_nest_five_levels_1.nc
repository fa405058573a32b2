#100=[[[[[1+1]]]]]
M30
(expect: #100=2 status=completed)
