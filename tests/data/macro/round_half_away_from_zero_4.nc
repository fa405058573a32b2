#100=ROUND[-1.4]
M30
(expect: #100=-1 status=completed)
