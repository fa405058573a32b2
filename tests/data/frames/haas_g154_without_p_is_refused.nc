(fivex: --dialect haas)
G154 G00 X1.
M30
(expect: alarm=331 alarm_line=2 wX=0)
