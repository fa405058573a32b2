(fivex: --preset mill3 --allow-unbuilt)
G68.2 P3 Q1 X0 Y0 Z0 I1. J0 K0
G68.2 P3 Q2 I0 J0 K1.
G69
M30
(expect: status=completed)
