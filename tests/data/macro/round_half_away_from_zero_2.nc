#100=ROUND[-2.5]
M30
(expect: #100=-3 status=completed)
