(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G41 D1 G01 X10. F100.
G01 X20. ,C1.
Y10.
G40 X30.
M30
(Chamfering under cutter compensation is not built: PS0010 / 310 at the ,C block.)
(expect: alarm[fanuc]=PS0010 alarm[haas]=310 alarm_line=4)
