#100=BIN[4660]
M30
(BCD 0x1234 = 4660 → binary 1234, and back.)
(expect: #100=1234 status=completed)
