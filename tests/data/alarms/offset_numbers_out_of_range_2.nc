(fivex: --dialect fanuc,syntec)
G54.1 P301
(expect: alarm[fanuc]=PS0030 alarm_line=2 alarm[syntec]=COR-011)
