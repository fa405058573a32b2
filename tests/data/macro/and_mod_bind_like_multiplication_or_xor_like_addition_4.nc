#100=1+2 XOR 3
M30
(XOR and + are one level, left to right: [1+2] XOR 3 = 0.)
(expect: #100=0 status=completed)
