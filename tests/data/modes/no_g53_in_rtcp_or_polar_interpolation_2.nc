(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G53 Z0
(expect: alarm=COR-118)
