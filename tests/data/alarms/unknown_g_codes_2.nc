(fivex: --dialect fanuc,syntec)
G43.45
(expect: alarm[fanuc]=PS0010 alarm_line=2 alarm[syntec]=COR-070)
