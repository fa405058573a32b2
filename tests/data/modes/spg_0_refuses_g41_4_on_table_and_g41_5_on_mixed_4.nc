(fivex: --preset table-bc --dialect syntec --allow-unbuilt)
G41.4 D1
G40
(expect: alarm=COR-070)
