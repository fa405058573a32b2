(fivex: --dialect fanuc,syntec)
#101=6
G65 P9500
M30
O9500
#100=#100+1
IF[#100GE#101]GOTO 9
G65 P9500
N9 M99
(expect: alarm[fanuc]=PS0077 alarm[syntec]=COR-031)
