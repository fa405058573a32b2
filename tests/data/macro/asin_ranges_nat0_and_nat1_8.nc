(fivex: --nat)
#100=ASIN[-1]
M30
(NAT=1: -90…90.)
(expect: #100=-90 status=completed)
