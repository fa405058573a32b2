(fivex: --dialect fanuc,syntec)
#100=1GT0
M30
(Decision: PS0125 [macro statement format error].)
(expect: alarm[fanuc]=PS0125 alarm[syntec]=COR-020)
