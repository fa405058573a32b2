(fivex: --dialect haas --workpiece block.json)
G90 G21 G54 G00 G43 H1 Z10.
X25. Y20.
G31 Z-10. F100. M79
#100=#5063
G00 Z10.
X60.
G31 Z-10. F100. M78
#101=#5063
M79
M30
(M79 after a touch and M78 after a move in air pass; the last M79 finds no touch: 749.)
(expect: #100=0~1e-9 #101=-10 alarm=749 alarm_line=10)
