#100=-10 MOD 3
M30
(…and the remainder has the dividend's sign [truncating division].)
(expect: #100=-1 status=completed)
