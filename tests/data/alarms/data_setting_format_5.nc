(fivex: --dialect fanuc,syntec)
G10 L2 P7 X1.
(expect: alarm[fanuc]=PS0031 alarm_line=2 alarm[syntec]=COR-046)
