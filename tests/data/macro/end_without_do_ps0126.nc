(fivex: --dialect fanuc,syntec)
#100=1
END1
M30
(expect: alarm[fanuc]=PS0126 alarm[syntec]=COR-028)
