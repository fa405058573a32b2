(fivex: --dialect fanuc,syntec)
M3.5 S1000
(A number written with a decimal point stays refused at a whole-number address.)
(expect: alarm[fanuc]=PS0009 alarm[syntec]=COR-002)
