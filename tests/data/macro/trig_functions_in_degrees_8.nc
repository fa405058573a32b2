#100=SIN[0]
M30
(expect: #100=0 status=completed)
