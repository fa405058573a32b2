(fivex: --preset head-bc --dialect syntec)
G43.4 H1 L1
G05 P10000
(expect: alarm=COR-140)
