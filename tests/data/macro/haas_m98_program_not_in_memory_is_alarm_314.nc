(fivex: --dialect haas)
M98 P4321
M30
(expect: alarm=314 alarm_line=2)
