(fivex: --dialect haas)
#100=1
[#100 EQ 1] G01 X5. F100. (ONLY M99 P MAY FOLLOW A CONDITION)
M30
(expect: alarm=540 alarm_line=3)
