(fivex: --dialect haas)
#100=1
[#100 GT 2] M99 P9 (FALSE: NO BRANCH; THE RUN DOES NOT LOOK FOR N9)
#101=2
M30
(expect: #100=1 #101=2 status=completed)
