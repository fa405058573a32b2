(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G41.6 D1
G01 X10. B10. F100
G40
(expect: alarm=COR-070)
