(fivex: --preset head-bc --allow-unbuilt)
G41.3 D1
F100
X10.
(crc CRC-21, TV-31 [the direction, PS5408, needs the tool vector])
(expect: alarm=PS5460)
