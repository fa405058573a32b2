#100=12 AND 10
M30
(expect: #100=8 status=completed)
