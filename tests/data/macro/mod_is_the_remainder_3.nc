#100=3 MOD 7
M30
(expect: #100=3 status=completed)
