(fivex: --dialect fanuc,syntec)
#101=16
M98 P100
M30
O0100
#100=#100+1
IF[#100GE#101]GOTO 9
M98 P100
N9 M99
(expect: alarm[fanuc]=PS0077 alarm[syntec]=COR-031)
