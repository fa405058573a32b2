(fivex: --preset head-bc --allow-unbuilt)
G41.3 D1 X10.
(crc CRC-21, §6.2, TV-31)
(expect: alarm=PS5460)
