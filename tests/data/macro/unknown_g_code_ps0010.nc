(fivex: --dialect syntec)
G53.3
M30
(expect: status=completed)
