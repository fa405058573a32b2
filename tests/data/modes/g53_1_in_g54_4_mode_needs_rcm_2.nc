(fivex: --preset head-bc --allow-unbuilt)
G68.2 X0 Y0 Z0 I0 J0 K0
G53.1
G69
M30
(expect: status=completed)
