(fivex: --dialect fanuc,syntec)
G00 Z10.
G73 X0 Y0 Z-5. R2. F100
(expect: alarm[fanuc]=PS0045 alarm_line=3 alarm[syntec]=COR-015)
