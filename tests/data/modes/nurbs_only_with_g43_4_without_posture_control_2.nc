(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1 P1
G06.2 P4 X1. Y0 Z0 F100
(expect: alarm=PS5421)
