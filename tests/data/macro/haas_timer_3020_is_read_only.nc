(fivex: --dialect haas)
#3020=0 (POWER ON TIMER: READ ONLY)
M30
(expect: alarm=522 alarm_line=2)
