(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G10 L5000 P2
(syn SYN-26, TV-23 [Syntec only])
(expect: alarm[fanuc]=PS1144 alarm[syntec]=COR-160)
