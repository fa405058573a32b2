#100=ASIN[0]
M30
(expect: #100=0 status=completed)
