(fivex: --dialect fanuc,syntec)
#1=2 X1.
(expect: alarm[fanuc]=PS0127 alarm_line=2 alarm[syntec]=COR-033)
