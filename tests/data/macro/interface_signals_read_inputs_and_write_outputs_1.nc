(fivex: --dialect fanuc,syntec)
#1000=1
(expect: alarm[fanuc]=PS0116 alarm[syntec]=COR-022)
