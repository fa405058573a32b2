(fivex: --dialect fanuc,syntec)
G65 P9000
M30
O9000
G65 P9000
M99
(expect: alarm[fanuc]=PS0077 alarm[syntec]=COR-031)
