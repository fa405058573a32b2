(fivex: --dialect fanuc,haas)
G90 G21 G54 G01 G43 H1 Z10. F500.
G31 Z0
M30
(The NGC's G31 page: the G31 line must have a feed. FANUC takes the modal F.)
(expect: alarm[haas]=320 alarm_line[haas]=3 status[fanuc]=completed wZ[fanuc]=0)
