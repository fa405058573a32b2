(fivex: --dialect fanuc,syntec)
#100=ATAN[0,0]
M30
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-004)
