(fivex: --dialect fanuc,syntec)
#100=BCD[1.5]
M30
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-004)
