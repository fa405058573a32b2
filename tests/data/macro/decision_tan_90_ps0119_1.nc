(fivex: --dialect fanuc,syntec)
#100=TAN[90]
M30
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-004)
