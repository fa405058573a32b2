(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X-20. Y-20. Z0
G41 D1 G01 X0 Y0 ,C1. F100.
X20.
G40 X30.
M30
(Under cutter compensation C a corner is built in offset mode only: a ,C in the start-up block)
([or the cancel block] is refused as not built, PS0010 / 310.)
(expect: alarm[fanuc]=PS0010 alarm[haas]=310 alarm_line=3)
