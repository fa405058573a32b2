(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
G91 G01 X100. ,C10. F1000.
X100. Y100.
G90
M30
(Mitsubishi M700V, 13.7.1 [secondary source: the same ,C of the FANUC form]: from X0 Y0 the)
(corner is X100 Y0; the chamfer starts 10 before it on the first line, X90 Y0, and ends 10 after)
(it on the second, which runs at 45 degrees: X100+10/sqrt2 = 107.0710678118655, Y7.0710678118655.)
(The second line then ends at X200 Y100. The held line and the chamfer are the first block's.)
(expect: feeds=X90,Y0/X107.0710678118655,Y7.0710678118655/X200,Y100 motions=4 status=completed)
(skip: limits@3 the chamfer is a motion of its block [line, N, F], so its two corners are inside one block: they take the planner's corner speed step, which the check allows only where the line changes)
