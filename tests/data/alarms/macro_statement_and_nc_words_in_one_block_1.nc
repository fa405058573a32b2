(fivex: --dialect fanuc,syntec)
G01 X1. #1=2
(expect: alarm[fanuc]=PS0127 alarm_line=2 alarm[syntec]=COR-033)
