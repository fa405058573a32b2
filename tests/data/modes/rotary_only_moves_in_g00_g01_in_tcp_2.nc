(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G01 B10. F100
G49
M30
(expect: status=completed)
