(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G92 X0
(tcp TCP-16, TV-63 [FANUC only; 3-axis machines have no TCP, decision])
(expect: alarm=PS5421)
