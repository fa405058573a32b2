(fivex: --preset head-bc --allow-unbuilt)
G02 X10. Y10. R10. F100
G41.3 D1
(crc CRC-21, §6.2, TV-31)
(expect: alarm=PS5460)
