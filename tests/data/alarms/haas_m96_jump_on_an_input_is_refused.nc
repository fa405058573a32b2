(fivex: --dialect fanuc,haas)
G00 X1.
M96 P10 Q8 (HAAS: JUMP TO N10 IF INPUT 8 IS 0)
G00 X5.
M30
N10 X9.
M30
(fivex has no discrete inputs: run on, the program would take a path the machine may not. FANUC
 has no M96: an auxiliary function, passed on.)
(expect: alarm[haas]=329 alarm_line[haas]=3 wX[haas]=1 status[fanuc]=completed wX[fanuc]=5)
