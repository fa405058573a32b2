(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1
G49
M30
(expect: status=completed)
