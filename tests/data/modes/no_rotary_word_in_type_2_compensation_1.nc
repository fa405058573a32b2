(fivex: --preset head-bc --allow-unbuilt)
G41.6 D1
G01 X10. B10. F100
(crc CRC-02, TV-18)
(expect: alarm=PS5460)
