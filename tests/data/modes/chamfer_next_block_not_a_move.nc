(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,C1. F100.
M05
M30
(The block after a ,C/,R block must be a G01 move in the plane: FANUC PS0051, Haas 750 [constructed].)
(expect: alarm[fanuc]=PS0051 alarm[haas]=750 alarm_line=4)
