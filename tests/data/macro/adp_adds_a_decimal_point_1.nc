#100=ADP[10]
M30
(IS-B metric: an integer-input value counts 0.001 mm.)
(expect: #100=0.01 status=completed)
