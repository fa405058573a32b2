IF[[[[[1]]]]EQ1]THEN#100=1
M30
(A condition's bracket counts too.)
(expect: #100=1 status=completed)
