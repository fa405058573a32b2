(fivex: --preset table-bc --allow-unbuilt)
G41.4 D1
(crc CRC-31/32, TV-17 [SPG = 0])
(expect: alarm=PS0010)
