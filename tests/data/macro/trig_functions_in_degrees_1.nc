#100=SIN[30]
M30
(expect: #100=0.5 status=completed)
