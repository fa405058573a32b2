(fivex: --dialect fanuc,syntec)
G00 Z10.
G81 X0 Y0 Z-5. R2. F100
G28 Z10.
(expect: alarm[fanuc]=PS0044 alarm_line=4 alarm[syntec]=COR-043)
