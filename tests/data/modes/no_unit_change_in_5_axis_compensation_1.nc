(fivex: --preset head-bc --allow-unbuilt)
G41.2 D1
G20
(crc CRC-46, §6.1, TV-29)
(expect: alarm=PS5000)
