(fivex: --dialect fanuc,syntec)
G17 G41 D1 G01 X10. F100
G18
(A plane change while cutter compensation is on.)
(expect: alarm[fanuc]=PS0037 alarm_line=3 alarm[syntec]=COR-013)
