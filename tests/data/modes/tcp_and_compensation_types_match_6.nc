(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G41.6 D1
G43.4 H1
G49
G40
(crc CRC-48, TV-18)
(expect: alarm=COR-070)
