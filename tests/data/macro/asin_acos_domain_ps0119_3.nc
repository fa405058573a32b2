(fivex: --dialect fanuc,syntec)
#100=ACOS[-1.1]
M30
(Decision: ACOS outside [-1, 1] is the same alarm.)
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-004)
