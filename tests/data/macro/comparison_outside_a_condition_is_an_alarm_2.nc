(fivex: --dialect fanuc,syntec)
#100=[1 EQ 1]
M30
(expect: alarm[fanuc]=PS0125 alarm[syntec]=COR-020)
