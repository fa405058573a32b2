#100=6 XOR 2*2
M30
(* before XOR: 6 XOR [2*2] = 2.)
(expect: #100=2 status=completed)
