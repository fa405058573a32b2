(fivex: --dialect fanuc,syntec)
#100=1
N20 [#100 LT 3] M99 P10
M30
(A block cannot start with a condition in these dialects.)
(expect: alarm[fanuc]=PS0004 alarm[syntec]=COR-001 alarm_line=3)
