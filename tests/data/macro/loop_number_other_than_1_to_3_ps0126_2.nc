(fivex: --dialect fanuc,syntec)
WHILE[1EQ1]DO0
END0
M30
(expect: alarm[fanuc]=PS0126 alarm[syntec]=COR-028)
