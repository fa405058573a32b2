(fivex: --dialect fanuc,syntec)
#1=0
WHILE[#1LT2]DO1
WHILE[#1LT2]DO2
#1=#1+1
END1
M30
(expect: alarm[fanuc]=PS0124 alarm[syntec]=COR-044)
