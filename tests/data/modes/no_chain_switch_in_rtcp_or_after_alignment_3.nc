(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.4 H1
G49
G10 L5000 P1
G68.2 X0 Y0 Z0 I0 J0 K0
G10 L5000 P1
G53.1
G69
G10 L5000 P1
(expect: status=completed)
