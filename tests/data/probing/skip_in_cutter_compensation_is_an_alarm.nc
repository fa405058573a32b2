(fivex: --dialect fanuc,syntec,haas)
G90 G21 G54 G00 G43 H1 Z10.
G41 D1 G01 X10. Y0 F100.
G31 X20. F100.
G40 X0
M30
(FANUC's PS0035; the NGC manual says not to use cutter compensation with G31.)
(expect: alarm[fanuc]=PS0035 alarm[syntec]=COR-041 alarm[haas]=747 alarm_line=4)
