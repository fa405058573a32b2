(fivex: --preset head-bc --allow-unbuilt)
G95
G43.4 H1
(tcp TCP-15, TV-64 [FANUC only])
(expect: alarm=PS5421)
