(fivex: --dialect syntec)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,C1. F100.
Y10.
M30
(No Syntec source gives its chamfer form: ,C stays refused as not built, COR-100.)
(expect: alarm=COR-100 alarm_line=3)
