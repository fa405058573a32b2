(fivex: --dialect haas)
#100=#3024
#3024=0 (LAST COMPLETE PART TIMER: READ ONLY)
M30
(expect: alarm=522 alarm_line=3 #100=0)
