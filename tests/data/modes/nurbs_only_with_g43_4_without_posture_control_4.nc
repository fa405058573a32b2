(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G06.2 P2 K0 F100
K0 X1.
K1.
K1.
G01 X2.
G49
M30
(expect: status=completed)
