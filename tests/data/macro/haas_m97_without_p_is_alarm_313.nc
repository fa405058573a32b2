(fivex: --dialect haas)
G00 X1.
M97 L2
M30
N10 X2.
M99
(expect: alarm=313 alarm_line=3 wX=1)
