(fivex: --dialect fanuc,syntec)
G00 X1.2.3
(expect: alarm[fanuc]=PS0004 alarm_line=2 alarm[syntec]=COR-001)
