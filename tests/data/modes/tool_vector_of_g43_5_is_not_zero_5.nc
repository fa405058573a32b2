(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G01 X10. K1. F100
X20.
G49
(expect: status=completed)
