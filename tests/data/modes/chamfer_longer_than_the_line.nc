(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,C11. F100.
Y10.
M30
(The chamfer, 11, is longer than the first line, 10: PS0055 MISSING MOVE VALUE IN CHF/CNR, Haas)
(752 [constructed]; raised when the next block is read.)
(expect: alarm[fanuc]=PS0055 alarm[haas]=752 alarm_line=4)
