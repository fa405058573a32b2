(fivex: --preset head-bc --allow-unbuilt)
G43.8 H1
G01 X10. F100
G49
M30
(expect: status=completed)
