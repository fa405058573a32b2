(fivex: --dialect fanuc,syntec)
WHILE[1EQ1]DO1
#100=1
M30
(expect: alarm[fanuc]=PS0124 alarm[syntec]=COR-044)
