(fivex: --preset table-bc --allow-unbuilt)
G41.3 D1
(crc CRC-34, §6.3, TV-31)
(expect: alarm=PS5460)
