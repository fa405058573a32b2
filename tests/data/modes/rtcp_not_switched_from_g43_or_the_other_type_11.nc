(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G43 H2 Z10.
G49
(SYN-07/08 "do not apply with G43, G44": a G43/G44 inside RTCP does not end it [only G49)
(does], it is refused like the switch the other way [COR-100]; FANUC: not in the TCP list.)
(expect: alarm[fanuc]=PS5421 alarm[syntec]=COR-100)
