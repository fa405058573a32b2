#100=COS[60]
M30
(expect: #100=0.5 status=completed)
