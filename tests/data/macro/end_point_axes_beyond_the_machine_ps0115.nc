(fivex: --dialect fanuc,syntec)
#100=#5004
M30
(mill3 has three axes: #5004 does not exist there…)
(expect: alarm[fanuc]=PS0115 alarm[syntec]=COR-016)
