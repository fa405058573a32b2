(fivex: --preset head-bc --allow-unbuilt)
G41.6 D1
G01 X10. I0 J0 K1. F100
G40 B0
M30
(expect: status=completed)
