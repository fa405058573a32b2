(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G01 X10. ,C1. F100.
G03 X20. Y10. R10.
M30
(A chamfer between a line and an arc: ,C is the chord from the corner on the arc [NCT 2000M,)
(16.1, secondary], the distance on the line. The arc from X10 Y0 to X20 Y10, R10 counter-)
(clockwise, is centred at X10 Y10. The line stops at X9 Y0; on the arc a chord of 1 subtends)
(phi = 2 asin[1/20]: X10 + 10 sin phi = 10 + 10 * 2 * 0.05 * sqrt[1 - 0.0025] = 10.998749217772,)
(Y10 - 10 cos phi = 10 - 10 * [1 - 2 * 0.05^2] = 0.05. The rest of the arc then runs to X20 Y10.)
(expect: feeds=X9,Y0/X10.998749217772~1e-9,Y0.05 motion4=X20,Y10 motions=4 status=completed)
