#100=5.6 AND 7
M30
(Decision: AND/OR/XOR work on the operands rounded half away from zero.)
(expect: #100=6 status=completed)
