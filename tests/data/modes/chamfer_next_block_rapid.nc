(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,C1. F100.
G00 Y10.
M30
(A rapid after the ,C block: FANUC PS0052 CODE IS NOT G01 AFTER CNR/CHF, Haas 751 [constructed].)
(expect: alarm[fanuc]=PS0052 alarm[haas]=751 alarm_line=4)
