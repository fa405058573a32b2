(fivex: --dialect fanuc,syntec)
G43 H1000 Z0
(expect: alarm[fanuc]=PS0030 alarm_line=2 alarm[syntec]=COR-011)
