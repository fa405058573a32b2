(fivex: --dialect fanuc,syntec)
G01.7 X1. F100
M30
(expect: alarm[fanuc]=PS0010 alarm[syntec]=COR-070)
