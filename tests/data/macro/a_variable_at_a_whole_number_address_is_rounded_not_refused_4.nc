(fivex: --dialect fanuc,syntec)
T5.5
(expect: alarm[fanuc]=PS0007 alarm[syntec]=COR-002)
