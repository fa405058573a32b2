#100=12 MOD 4
M30
(expect: #100=0 status=completed)
