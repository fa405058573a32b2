(fivex: --dialect haas)
#100=0
M98 P2000
#101=#100
M30
O02000
N1 #100=#100+1
[#100 LT 5] M99 P1 (BRANCHES TO N1 WHILE #100 IS LESS THAN 5)
#102=7
M99
(The branch stays in the subprogram, which then returns with its M99.)
(expect: #100=5 #101=5 #102=7 status=completed)
