(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1
G91
G90 G49
M30
(syn SYN-08, TV-14 [Syntec only])
(expect: status=completed)
