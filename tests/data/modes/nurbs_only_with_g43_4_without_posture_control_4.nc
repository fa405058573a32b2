(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G06.2 P4 X1. Y0 Z0 F100
G01 X2.
G49
(expect: status=completed)
