(fivex: --dialect fanuc,syntec)
#100=LN[0]
M30
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-004)
