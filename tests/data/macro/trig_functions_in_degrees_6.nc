#100=SIN[-90]
M30
(expect: #100=-1 status=completed)
