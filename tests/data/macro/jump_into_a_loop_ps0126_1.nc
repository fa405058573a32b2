(fivex: --dialect fanuc,syntec)
#1=0
GOTO 10
WHILE[#1LT3]DO1
N10 #1=#1+1
END1
M30
(expect: alarm[fanuc]=PS0126 alarm[syntec]=COR-028)
