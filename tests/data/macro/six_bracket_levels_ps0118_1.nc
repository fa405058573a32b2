(fivex: --dialect fanuc,syntec)
#100=[[[[[[1]]]]]]
M30
(expect: alarm[fanuc]=PS0118 alarm[syntec]=COR-024)
