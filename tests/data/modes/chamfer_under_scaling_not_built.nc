(fivex: --dialect fanuc)
G90 G21 G54 G00 X0 Y0 Z0
G51 X0 Y0 P2.
G01 X10. ,C1. F100.
Y10.
G50
M30
(Whether scaling scales the chamfer no source says: ,C under G51 is refused as not built, PS0010.)
(expect: alarm=PS0010 alarm_line=4)
