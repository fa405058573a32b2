(fivex: --dialect fanuc,syntec)
#100=EXP[1000]
M30
(EXP has no domain limit; a result that is not finite is FANUC's PS0111.)
(expect: alarm[fanuc]=PS0111 alarm[syntec]=COR-026)
