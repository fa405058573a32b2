(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G02 X10. Y10. R10. F100
G41.3 D1
G01 X20.
G40
(expect: alarm=COR-070)
