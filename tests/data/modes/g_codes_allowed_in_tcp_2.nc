(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.4 H1
G28 Z0
G80
G49
(tcp TCP-16, TV-63 [FANUC only; 3-axis machines have no TCP, decision])
(syn §2.2.2 #4: G49 before G28; Syntec names no alarm, fivex refuses it under RTCP, decision: COR-100)
(expect: alarm=COR-100 alarm_line=3)
