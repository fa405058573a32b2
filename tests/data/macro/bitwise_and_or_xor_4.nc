#100=255 AND 15
M30
(expect: #100=15 status=completed)
