(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1 P1
G05.1 Q3 X0 Y0 Z0 B0 C0
(expect: alarm=PS5421)
