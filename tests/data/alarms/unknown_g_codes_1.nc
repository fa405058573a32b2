(fivex: --dialect fanuc,syntec)
G12.3
(expect: alarm[fanuc]=PS0010 alarm_line=2 alarm[syntec]=COR-070)
