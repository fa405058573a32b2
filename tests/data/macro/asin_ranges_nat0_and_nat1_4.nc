(fivex: --nat)
#100=ASIN[-0.5]
M30
(expect: #100=-30 status=completed)
