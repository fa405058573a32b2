(fivex: --preset head-bc --allow-unbuilt)
G41.2 D1
G43.4 H1
G40 G49
M30
(expect: status=completed)
