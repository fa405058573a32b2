(fivex: --dialect syntec)
#100=1
N20 #3000=12 (TOOL BROKEN)
#101=1
M30
(expect: alarm=MAR-012 alarm_line=3 status=alarm)
