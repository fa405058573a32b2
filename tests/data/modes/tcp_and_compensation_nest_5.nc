(fivex: --preset head-bc --allow-unbuilt)
G41.2 D1
G43.4 H1
G49
G40
M30
(expect: status=completed)
