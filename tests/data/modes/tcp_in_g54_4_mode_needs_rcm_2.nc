(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G54.4 P1
G43.4 H1
G49
(expect: alarm=COR-070)
