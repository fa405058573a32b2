(fivex: --dialect fanuc,syntec)
G10 L10 P1
(expect: alarm[fanuc]=PS1144 alarm_line=2 alarm[syntec]=COR-014)
