(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G49
G68.2 X0 Y0 Z0 I0 J0 K0
G53.1
G43 H1
G49
G69
M30
(expect: status=completed)
