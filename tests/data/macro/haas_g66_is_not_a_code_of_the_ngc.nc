(fivex: --dialect haas)
G66 P3000 A1.
M30
O3000
M99
(expect: alarm=310 alarm_line=2)
