#100=ACOS[-1]
M30
(expect: #100=180 status=completed)
