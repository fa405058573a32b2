(fivex: --dialect fanuc,syntec)
#501=6
G65 P9500
M30
O9500
#500=#500+1
IF[#500GE#501]GOTO 9
G65 P9500
N9 M99
(expect: alarm[fanuc]=PS0077 alarm[syntec]=COR-031)
