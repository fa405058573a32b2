#100=COS[90]
M30
(expect: #100=0 status=completed)
