(fivex: --dialect fanuc,syntec)
#100=ASIN[1.1]
M30
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-004)
