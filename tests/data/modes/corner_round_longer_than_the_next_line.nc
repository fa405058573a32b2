(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,R5. F100.
Y3.
M30
(A right angle with R5 needs 5 of each line; the second is 3: PS0055 / 752.)
(expect: alarm[fanuc]=PS0055 alarm[haas]=752 alarm_line=4)
