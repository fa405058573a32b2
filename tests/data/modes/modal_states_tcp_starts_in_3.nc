(fivex: --preset head-bc --allow-unbuilt)
G54.1 P1
G43.4 H1
(tcp TCP-15, TV-64 [FANUC only])
(expect: alarm=PS5421)
