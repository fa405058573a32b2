(fivex: --dialect fanuc,syntec)
G00 X1234567890123456
(expect: alarm[fanuc]=PS0003 alarm_line=2 alarm[syntec]=COR-042)
