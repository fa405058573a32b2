(fivex: --dialect fanuc,syntec)
M98 P100
M30
O0100
M98 P100
M99
(expect: alarm[fanuc]=PS0077 alarm[syntec]=COR-031)
