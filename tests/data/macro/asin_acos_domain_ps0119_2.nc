(fivex: --dialect fanuc,syntec)
#100=ASIN[-1.0001]
M30
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-004)
