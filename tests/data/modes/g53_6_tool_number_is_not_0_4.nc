(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G68.2 X0 Y0 Z0 I0 J0 K0
G53.6 H1
G49
G53.6
G49
G69
(expect: status=completed)
