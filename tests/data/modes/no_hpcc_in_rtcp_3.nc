(fivex: --preset head-bc --dialect syntec)
G43.4 H1
G05 P0
G49
(expect: status=completed)
