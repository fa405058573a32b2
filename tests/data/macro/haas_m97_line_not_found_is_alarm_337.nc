(fivex: --dialect haas)
G00 X1.
M97 P20
M30
N10 X2.
M99
(expect: alarm=337 alarm_line=3 wX=1)
