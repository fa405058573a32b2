(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G18 G01 Z-10. ,C2. F300.
X10.
G17
M30
(G18: the plane is Z-X. From Z0 the corner is Z-10 X0; the next line runs along +X. The chamfer)
(runs from Z-8 X0 to Z-10 X2.)
(expect: feeds=X0,Z-8/X2,Z-10/X10,Z-10 status=completed)
(skip: limits@3 the chamfer is a motion of its block [line, N, F], so its two corners are inside one block: they take the planner's corner speed step, which the check allows only where the line changes)
