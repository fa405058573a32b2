(fivex: --dialect fanuc,syntec)
#100=POW[-8,1./3]
M30
(A negative base with a fractional exponent, and 0 to a power ≤ 0.)
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-122)
