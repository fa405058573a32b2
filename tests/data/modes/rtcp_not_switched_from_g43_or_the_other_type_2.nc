(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G44 H1
G43.5 H1
(expect: alarm=COR-100)
