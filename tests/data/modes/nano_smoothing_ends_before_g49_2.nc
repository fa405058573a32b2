(fivex: --preset head-bc --allow-unbuilt)
G05.1 Q3 X0 Y0 Z0 B0 C0
G43.4 H1
G49
G05.1 Q0
(crc NSM-05, §6.7: G43.4 first, then G05.1 Q3 [order alarm not stated: PS5421, decision])
(expect: alarm=PS5421)
