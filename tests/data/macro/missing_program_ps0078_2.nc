(fivex: --dialect fanuc,syntec)
G65 P1234 A1.
M30
(expect: alarm[fanuc]=PS0078 alarm[syntec]=COR-030)
