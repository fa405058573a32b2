(fivex: --dialect fanuc,syntec)
G28 G92 X0
(expect: alarm[fanuc]=PS0010 alarm_line=2 alarm[syntec]=COR-070)
