(fivex: --dialect fanuc,syntec)
#1=0
WHILE[#1LT2]DO1
#1=#1+1
GOTO 20
WHILE[#1LT5]DO2
N20 #100=1
END2
END1
M30
(expect: alarm[fanuc]=PS0126 alarm[syntec]=COR-028)
