(fivex: --preset head-bc --allow-unbuilt)
G42.2 D1
G43.5 H1
(crc CRC-48, TV-18)
(expect: alarm=PS5460)
