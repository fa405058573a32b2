(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G05.1 Q3 X0 Y0 Z0 B0 C0
G05.1 Q0
G49
M30
(expect: status=completed)
