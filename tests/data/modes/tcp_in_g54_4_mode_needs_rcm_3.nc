(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G49
G54.4 P1
G54.4 P0
M30
(expect: status=completed)
