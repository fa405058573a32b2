(fivex: --dialect fanuc,syntec)
G17 G02 X10. Y0 I3. J0 F100
(expect: alarm[fanuc]=PS0020 alarm_line=2 alarm[syntec]=COR-012)
