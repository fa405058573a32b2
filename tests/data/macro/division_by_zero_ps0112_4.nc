(fivex: --dialect fanuc,syntec)
#100=7 MOD 0.4
M30
(Decision: MOD rounds its divisor first, so MOD 0.4 divides by 0.)
(expect: alarm[fanuc]=PS0112 alarm[syntec]=COR-004)
