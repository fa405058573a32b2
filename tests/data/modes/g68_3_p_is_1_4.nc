(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G68.3 P1 X0 Y0 Z0
G69
(expect: status=completed)
