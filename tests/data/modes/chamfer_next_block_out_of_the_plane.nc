(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,C1. F100.
Y10. Z-1.
M30
(The next block moves Z, off the G17 plane: PS0051 / 750.)
(expect: alarm[fanuc]=PS0051 alarm[haas]=750 alarm_line=4)
