(fivex: --dialect fanuc,haas)
G00 X1.
G54.1 P2 G00 X5.
M30
(The NGC selects its extra work offsets with G154 P: G54.1 is no code of it.)
(expect: status[fanuc]=completed wX[fanuc]=5 alarm[haas]=310 alarm_line[haas]=3 wX[haas]=1)
