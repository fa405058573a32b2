(fivex: --dialect fanuc,syntec)
G00 X1.
G00 A10.
(expect: alarm[fanuc]=PS0009 alarm_line=3 alarm[syntec]=COR-002)
