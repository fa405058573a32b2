(fivex: --dialect fanuc,syntec)
G90 X[1LT2]
M30
(expect: alarm[fanuc]=PS0125 alarm[syntec]=COR-020)
