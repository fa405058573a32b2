(fivex: --dialect haas)
#3026=5
M30
(expect: alarm=522 alarm_line=2)
