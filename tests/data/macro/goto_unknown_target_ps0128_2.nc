(fivex: --dialect fanuc,syntec)
#1=77
GOTO#1
M30
(expect: alarm[fanuc]=PS0128 alarm[syntec]=COR-029)
