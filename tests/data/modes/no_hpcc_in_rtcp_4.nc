(fivex: --preset head-bc --dialect syntec)
G05 P10000
G05 P0
G43.4 H1
G49
(expect: status=completed)
