(fivex: --dialect haas)
#3000=15 (PART MISSING)
M30
(expect: alarm=1015 alarm_line=2)
