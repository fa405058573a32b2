(fivex: --preset head-bc --allow-unbuilt)
G21
G41.2 D1
G40
G20
M30
(expect: status=completed)
