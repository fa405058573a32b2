(fivex: --dialect fanuc,syntec)
IF[[[[[[1]]]]]EQ1]THEN#100=1
M30
(expect: alarm[fanuc]=PS0118 alarm[syntec]=COR-024)
