#100=1+7 MOD 4
M30
(MOD before +: 1+[7 MOD 4] = 4.)
(expect: #100=4 status=completed)
