(fivex: --dialect fanuc,syntec)
#1000000=1
(expect: alarm[fanuc]=PS0115 alarm[syntec]=COR-016)
