(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G91
G43.5 H1
(syn SYN-08, TV-14 [Syntec only])
(expect: alarm=COR-305)
