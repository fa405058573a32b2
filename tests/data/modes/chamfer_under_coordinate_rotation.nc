(fivex: --dialect fanuc)
G90 G21 G54 G00 X0 Y0 Z0
G68 X0 Y0 R90.
G00 X0 Y30.
G01 X20. Y30. ,C3. F500.
Y0
G69
M30
(Programmed: from X0 Y30 to the corner X20 Y30, chamfer X17 Y30 to X20 Y27, then to X20 Y0.)
(G68 R90 about X0 Y0 turns every point [x, y] to [-y, x]: the chamfer, built on the turned lines,)
(runs from X-30 Y17 to X-27 Y20, and the line ends at X0 Y20 - the programmed chamfer, turned.)
(expect: feeds=X-30,Y17/X-27,Y20/X0,Y20 status=completed)
(skip: limits@5 the chamfer is a motion of its block [line, N, F], so its two corners are inside one block: they take the planner's corner speed step, which the check allows only where the line changes)
