(fivex: --dialect fanuc,syntec)
G66.1 P1234
M30
(expect: alarm[fanuc]=PS0078 alarm[syntec]=COR-100)
