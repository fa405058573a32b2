(fivex: --dialect fanuc,syntec)
GOTO 99
N10 M30
(expect: alarm[fanuc]=PS0128 alarm[syntec]=COR-029)
