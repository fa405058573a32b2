(fivex: --dialect syntec)
#100=1
N20 #3000=12 (TOOL BROKEN)
#101=1
M30
(#3000 is a modal variable on Syntec, which raises alarms with ALARM: refused, docs/dialects.md.)
(expect: alarm=COR-016 alarm_line=3 status=alarm)
