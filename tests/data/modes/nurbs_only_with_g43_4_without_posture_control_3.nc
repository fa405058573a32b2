(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G06.2 P4 X1. Y0 Z0 F100
G01
G49
(expect: status=completed)
