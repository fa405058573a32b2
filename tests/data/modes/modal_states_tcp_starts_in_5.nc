(fivex: --preset head-bc --allow-unbuilt)
G68 X0 Y0 R10.
G43.4 H1
(tcp TCP-15, TV-64 [FANUC only])
(expect: alarm=PS5421)
