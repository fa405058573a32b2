(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G91
(syn SYN-08, TV-14 [Syntec only])
(expect: alarm=COR-305)
