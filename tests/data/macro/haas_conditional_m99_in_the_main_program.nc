(fivex: --dialect haas)
#100=0
N10 #100=#100+1
N20 [#100 LT 3] M99 P10
#101=#100
M30
(The NGC manual's conditional M99: the branch to N10 only while #100 is less than 3.)
(expect: #100=3 #101=3 status=completed)
