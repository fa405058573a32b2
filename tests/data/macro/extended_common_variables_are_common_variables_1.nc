(fivex: --dialect fanuc,syntec)
#200000=1
(Between and beyond them there is nothing.)
(expect: alarm[fanuc]=PS0115 alarm[syntec]=COR-016)
