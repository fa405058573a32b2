(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G41.2 D1
G49
(crc CRC-48, TV-22)
(expect: alarm=PS5460)
