(fivex: --dialect fanuc,syntec)
G10 L2 X10.
(expect: alarm[fanuc]=PS1144 alarm_line=2 alarm[syntec]=COR-014)
