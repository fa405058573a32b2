(fivex: --preset mill3 --allow-unbuilt)
G61
G93
G56
G20
G68.2 X0 Y0 Z0 I0 J0 K0
G69
M30
(expect: status=completed)
