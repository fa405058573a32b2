(fivex: --preset mixed-bc --dialect syntec --allow-unbuilt)
G41.5 D1
G40
(expect: alarm=COR-070)
