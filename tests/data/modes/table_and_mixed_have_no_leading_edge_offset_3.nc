(fivex: --preset table-bc --dialect syntec --allow-unbuilt)
G41.3 D1
X10.
G40
(expect: alarm=COR-070)
