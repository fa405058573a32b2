(fivex: --dialect fanuc,haas --workpiece block.json)
G90 G21 G54 G00 G49 Z300.
X25. Y20.
G31 Z-10. F100.
M30
(Under G49 the tool's real length is not known to fivex [the offsets are not the tool]: a skip
 move toward a workpiece is refused rather than probed with the spindle nose.)
(expect: alarm[fanuc]=PS0010 alarm[haas]=310 alarm_line=4)
