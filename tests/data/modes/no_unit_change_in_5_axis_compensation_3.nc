(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G41.2 D1
G21
G40
(expect: alarm=COR-070)
