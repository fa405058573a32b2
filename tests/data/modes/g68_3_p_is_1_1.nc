(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G68.3 P2
(syn SYN-24, TV-21 [Syntec only])
(expect: alarm=COR-141)
