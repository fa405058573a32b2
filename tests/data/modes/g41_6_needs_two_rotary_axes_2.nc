(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G41.6 D1
G40
(expect: alarm=COR-070)
