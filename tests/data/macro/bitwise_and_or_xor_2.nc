#100=12 OR 10
M30
(expect: #100=14 status=completed)
