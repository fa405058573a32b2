(fivex: --dialect fanuc,syntec)
#100=7 MOD 0
M30
(expect: alarm[fanuc]=PS0112 alarm[syntec]=COR-004)
