(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,C1. ,R1. F100.
Y10.
M30
(One of ,C and ,R per block: both are PS0009 / 311 [decision].)
(expect: alarm[fanuc]=PS0009 alarm[haas]=311 alarm_line=3)
