(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,R1. F100.
M30
(M30 after a ,R block: the corner's next move never comes, PS0051 / 750.)
(expect: alarm[fanuc]=PS0051 alarm[haas]=750 alarm_line=4)
