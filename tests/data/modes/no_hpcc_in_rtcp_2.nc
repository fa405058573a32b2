(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.4 H1 L1
G05 P10000
(expect: alarm=COR-140)
