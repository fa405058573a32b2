(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G06.2 P2 K0 F100
K0 X1.
K1.
K1.
G49
(G49 while G06.2 is the group-01 mode: tcp TCP-17.)
(expect: alarm=PS5421)
