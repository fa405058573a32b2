(fivex: --dialect fanuc,syntec)
#100=BIN[26]
M30
(0x1A is not a BCD number; BCD of a negative number does not exist.)
(expect: alarm[fanuc]=PS0119 alarm[syntec]=COR-004)
