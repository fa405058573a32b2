#100=1
N20 #3000=12 (TOOL BROKEN)
#101=1
M30
(The program stops there.)
(expect: alarm=MC3012 alarm_line=2 status=alarm commons=100:1)
