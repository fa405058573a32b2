#100=ADP[12345]
M30
(expect: #100=12.345 status=completed)
