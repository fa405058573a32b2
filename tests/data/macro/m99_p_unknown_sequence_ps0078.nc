(fivex: --dialect fanuc,syntec)
M98 P20
M30
O0020
M99 P77
(expect: alarm[fanuc]=PS0078 alarm[syntec]=COR-030)
