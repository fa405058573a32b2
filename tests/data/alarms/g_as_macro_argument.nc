(fivex: --dialect fanuc,syntec)
O1
G65 P2 G01 A1.
M30
O2
M99
(expect: alarm[fanuc]=PS0129 alarm_line=3 alarm[syntec]=COR-032)
