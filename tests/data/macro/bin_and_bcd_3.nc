#100=BIN[BCD[987]]
M30
(expect: #100=987 status=completed)
