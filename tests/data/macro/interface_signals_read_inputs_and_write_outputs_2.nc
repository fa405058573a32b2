(fivex: --dialect fanuc,syntec)
#1100=2
(expect: alarm[fanuc]=PS0115 alarm[syntec]=COR-016)
