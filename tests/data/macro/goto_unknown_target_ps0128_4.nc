(fivex: --dialect fanuc,syntec)
IF[1EQ1]GOTO 99
M30
(expect: alarm[fanuc]=PS0128 alarm[syntec]=COR-029)
