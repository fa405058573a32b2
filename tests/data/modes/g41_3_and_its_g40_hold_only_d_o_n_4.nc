(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G41.3 D1 X10.
G40 X0
(expect: alarm=COR-070)
