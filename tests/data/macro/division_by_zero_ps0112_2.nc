(fivex: --dialect fanuc,syntec)
#100=1/#1
M30
(expect: alarm[fanuc]=PS0112 alarm[syntec]=COR-004)
