(fivex: --dialect fanuc,syntec)
M98
M30
(expect: alarm[fanuc]=PS0078 alarm[syntec]=COR-100)
