(fivex: --preset head-bc --allow-unbuilt)
G68.3 P2
G69
M30
(expect: status=completed)
