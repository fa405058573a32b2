(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.8 H1
G02 X10. Y10. R10. F100
G01
G49
(expect: alarm=COR-070)
