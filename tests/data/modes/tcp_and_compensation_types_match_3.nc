(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1
G41.2 D1
(crc CRC-48, TV-18)
(expect: alarm=PS5460)
