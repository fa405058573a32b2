(fivex: --dialect fanuc,syntec)
#[0]=1
M30
(expect: alarm[fanuc]=PS0116 alarm[syntec]=COR-022)
