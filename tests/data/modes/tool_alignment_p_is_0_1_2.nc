(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G68.2 X0 Y0 Z0 I0 J0 K0
G53.1 P2
G53.3 P0
G53.6 H1 P1
G49
G69
(expect: status=completed)
