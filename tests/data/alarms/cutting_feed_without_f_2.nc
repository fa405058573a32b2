(fivex: --dialect fanuc,syntec)
G01 X10. F0
(expect: alarm[fanuc]=PS0011 alarm_line=2 alarm[syntec]=COR-010)
