(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G02 X10. Y10. R10. ,C2. F200.
G01 Y0
M30
(A chamfer after an arc: the arc from X0 Y0 to X10 Y10, R10 clockwise, is centred at X10 Y0 and)
(ends going +X; the line then goes -Y. On the arc a chord of 2 back from the corner subtends)
(phi = 2 asin[2/20]: the arc stops at X10 - 10 sin phi = 10 - 10 * 2 * 0.1 * sqrt[0.99] =)
(8.010025125787, Y10 cos phi = 10 * [1 - 2 * 0.01] = 9.8, turning -[90 - 11.478340] degrees; the)
(chamfer runs to X10 Y8 [2 down the line] and the line on to X10 Y0.)
(expect: motion2=X8.010025125787~1e-9,Y9.8 feeds=X10,Y8/X10,Y0 motions=4 status=completed)
(skip: limits@3 the chamfer is a motion of its block [line, N, F], so its two corners are inside one block: they take the planner's corner speed step, which the check allows only where the line changes)
