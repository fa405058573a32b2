(fivex: --preset head-bc --allow-unbuilt)
G41.2 D1
G01 X10. F100
G43.4 H1
G49
G40 G80
G28 Z0
M30
(expect: status=completed)
