(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1
G05.1 Q3 X0 Y0 Z0 B0 C0
(crc NSM-05, TV-38)
(expect: alarm=PS5421)
