(fivex: --dialect fanuc,syntec)
G10 L10 P1
(expect: alarm[fanuc]=PS0031 alarm_line=2 alarm[syntec]=COR-046)
