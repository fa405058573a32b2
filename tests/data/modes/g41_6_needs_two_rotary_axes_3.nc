(fivex: --preset head-bc --allow-unbuilt)
G41.6 D1
G40
M30
(expect: status=completed)
