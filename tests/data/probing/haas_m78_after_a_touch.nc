(fivex: --dialect haas --workpiece block.json)
G90 G21 G54 G00 G43 H1 Z10.
X25. Y20.
G31 Z-10. F100. M78
M30
(The probe touches the top: M78 in the G31's own line alarms after the move.)
(expect: alarm=748 alarm_line=4 wZ=0~1e-9)
