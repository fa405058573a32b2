(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G00 X10. ,C1.
G01 Y10. F100.
M30
(,C on a G00 block: not built [no chamfer between rapids], PS0009 / 311.)
(expect: alarm[fanuc]=PS0009 alarm[haas]=311 alarm_line=3)
