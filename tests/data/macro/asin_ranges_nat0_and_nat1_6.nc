#100=ASIN[-1]
M30
(NAT=0: 270…90 [negative results as 270…360].)
(expect: #100=270 status=completed)
