#100=10 MOD 2.6
M30
(expect: #100=1 status=completed)
