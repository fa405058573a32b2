#100=ACOS[0.5]
M30
(expect: #100=60 status=completed)
