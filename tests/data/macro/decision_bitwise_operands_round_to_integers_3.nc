#100=2.5 XOR 0
M30
(expect: #100=3 status=completed)
