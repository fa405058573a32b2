#100=SIN[30]*2
M30
(expect: #100=1 status=completed)
