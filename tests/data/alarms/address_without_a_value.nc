(fivex: --dialect fanuc,syntec)
G00 X
(expect: alarm[fanuc]=PS0005 alarm_line=2 alarm[syntec]=COR-003)
