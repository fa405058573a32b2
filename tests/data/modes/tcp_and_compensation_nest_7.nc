(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G41.2 D1
G43.4 H1
G40
G49
G40
(crc CRC-48, TV-22)
(expect: alarm=COR-070)
