(fivex: --preset mill3 --allow-unbuilt)
G54.4 P1
G68.2 X0 Y0 Z0 I0 J0 K0
G69
G54.4 P0
M30
(expect: status=completed)
