(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,C1. F100.
G03 X20. Y10. R10.
M30
(FANUC allows a line-arc corner; fivex builds line-line only: the arc block is refused as not)
(built, PS0010 / 310.)
(expect: alarm[fanuc]=PS0010 alarm[haas]=310 alarm_line=4)
