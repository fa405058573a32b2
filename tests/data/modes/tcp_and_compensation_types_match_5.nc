(fivex: --preset head-bc --allow-unbuilt)
G41.6 D1
G43.4 H1
(crc CRC-48, TV-18)
(expect: alarm=PS5460)
