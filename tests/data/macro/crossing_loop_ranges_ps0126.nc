(fivex: --dialect fanuc,syntec)
#1=0
WHILE[#1LT2]DO1
#2=0
WHILE[#2LT2]DO2
#2=#2+1
END1
#1=#1+1
END2
M30
(expect: alarm[fanuc]=PS0126 alarm[syntec]=COR-028)
