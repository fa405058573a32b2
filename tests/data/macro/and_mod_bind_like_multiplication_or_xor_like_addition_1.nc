#100=4 OR 1 AND 2
M30
(AND before OR: 4 OR [1 AND 2] = 4 [not [4 OR 1] AND 2 = 0].)
(expect: #100=4 status=completed)
