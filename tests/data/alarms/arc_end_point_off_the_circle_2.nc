(fivex: --dialect fanuc,syntec)
G17 G02 X10. Y0 R4. F100
(R smaller than half the chord.)
(expect: alarm[fanuc]=PS0020 alarm_line=2 alarm[syntec]=COR-012)
