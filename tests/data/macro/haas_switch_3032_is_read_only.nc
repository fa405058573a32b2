(fivex: --dialect haas)
#3032=1 (BLOCK DELETE: THE OPERATOR'S SWITCH, READ ONLY)
M30
(expect: alarm=522 alarm_line=2)
