(fivex: --dialect fanuc,syntec)
GOTO#1
N0 M30
(A vacant target is no target.)
(expect: alarm[fanuc]=PS0128 alarm[syntec]=COR-029)
