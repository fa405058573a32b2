#100=1
#100=-#1
M30
(Decision: `-#1` and `[#1]` keep the vacancy of a lone variable.)
(expect: #100=vacant status=completed)
