#100=ASIN[1]
M30
(expect: #100=90 status=completed)
