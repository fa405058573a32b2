(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G05.1 Q3 X0 Y0 Z0 B0 C0
G49
(crc §6.7, OQ-29 [alarm not stated: PS5421, decision; FANUC only])
(expect: alarm[fanuc]=PS5421 status[syntec]=completed)
