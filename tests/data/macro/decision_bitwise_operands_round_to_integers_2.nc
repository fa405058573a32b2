#100=1.4 OR 2
M30
(expect: #100=3 status=completed)
