(fivex: --preset mill3 --allow-unbuilt)
G43.4 H1
G07.1
G80
G49
M30
(tcp TCP-16, TV-63 [FANUC only; 3-axis machines have no TCP, decision])
(expect: status=completed)
