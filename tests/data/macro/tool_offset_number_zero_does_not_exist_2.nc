(fivex: --dialect fanuc,syntec)
#100=#2000
M30
(expect: alarm[fanuc]=PS0115 alarm[syntec]=COR-016)
