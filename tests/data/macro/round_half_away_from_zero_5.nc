#100=ROUND[0.5]
M30
(expect: #100=1 status=completed)
