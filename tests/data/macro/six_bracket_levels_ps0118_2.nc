(fivex: --dialect fanuc,syntec)
#100=SIN[[[[[[90]]]]]]
M30
(expect: alarm[fanuc]=PS0118 alarm[syntec]=COR-024)
