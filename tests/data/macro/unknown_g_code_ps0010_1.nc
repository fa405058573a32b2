(fivex: --dialect fanuc,syntec)
G120
M30
(expect: alarm[fanuc]=PS0010 alarm[syntec]=COR-070)
