(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G12.1
G53 X0
(expect: alarm=COR-118)
