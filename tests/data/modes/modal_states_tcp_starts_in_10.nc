(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G41.1
G43.4 H1
G49
(tcp TCP-15, TV-64 [FANUC only])
(expect: status=completed)
