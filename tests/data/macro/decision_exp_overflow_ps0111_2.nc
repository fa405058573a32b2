#100=EXP[-1000]
M30
(expect: #100=0 status=completed)
