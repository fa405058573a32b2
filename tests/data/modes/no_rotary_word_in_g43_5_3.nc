(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.5 H1
G01 X10. I0 J0 K1. F100
G49 B0
M30
(expect: status=completed)
