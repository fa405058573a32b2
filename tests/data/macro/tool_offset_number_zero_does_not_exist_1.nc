(fivex: --dialect fanuc,syntec)
#10000=1.
M30
(expect: alarm[fanuc]=PS0115 alarm[syntec]=COR-016)
