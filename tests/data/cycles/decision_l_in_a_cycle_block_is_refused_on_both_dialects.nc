(fivex: --dialect fanuc,syntec)
G90 G00 X0 Y0 Z20.
G91 G81 X10. R-15. Z-7. L3 F300.
M30
(expect: alarm[fanuc]=PS0009 alarm[syntec]=COR-002)
