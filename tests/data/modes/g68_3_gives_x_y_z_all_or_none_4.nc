(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G68.3 X0 Y0 Z0
G69
G68.3
G69
G68.3 R30.
G69
M30
(expect: status=completed)
