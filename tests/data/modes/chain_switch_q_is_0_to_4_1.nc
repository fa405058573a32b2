(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G10 L5000 P1 Q5
(syn SYN-26, TV-22 [Syntec only; FANUC has no G10 L5000])
(expect: alarm[fanuc]=PS1144 alarm[syntec]=COR-163)
