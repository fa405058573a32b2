(fivex: --preset mill3 --allow-unbuilt)
G41.6 D1
(crc CRC-02, TV-18)
(expect: alarm=PS5460)
