#100=10 MOD -3
M30
(expect: #100=1 status=completed)
