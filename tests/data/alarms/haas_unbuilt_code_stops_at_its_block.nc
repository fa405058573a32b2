(fivex: --dialect haas)
G00 X1.
G187 P1 (SMOOTHNESS LEVEL: NOT BUILT IN FIVEX)
G00 X5.
M30
(expect: alarm=310 alarm_line=3 wX=1)
