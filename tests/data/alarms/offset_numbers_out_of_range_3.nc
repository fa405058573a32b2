(fivex: --dialect fanuc,syntec)
D-1 X1.
(expect: alarm[fanuc]=PS0030 alarm_line=2 alarm[syntec]=COR-011)
