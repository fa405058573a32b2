#100=COS[180]
M30
(expect: #100=-1 status=completed)
