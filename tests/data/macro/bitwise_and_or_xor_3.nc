#100=12 XOR 10
M30
(expect: #100=6 status=completed)
