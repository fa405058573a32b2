(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
N1 G01 X40. ,R5. F1000.
N2 Y30. ,C4. F500.
#100 = 1
N3 X0 ,R10.
N4 Y0
M30
(Corner X40 Y0, R5, +X to +Y [left]: tangent points X35 Y0 and X40 Y5, counter-clockwise about)
(X35 Y5. N2's line then starts at X40 Y5 and its corner X40 Y30 has C4: X40 Y26 to X36 Y30 [at)
(N2's F500]. A macro statement between two blocks is no block of the corner. N3's line starts)
(at X36 Y30; corner X0 Y30, R10, -X to -Y [left]: X10 Y30 to X0 Y20 about X10 Y20. N4 ends at X0 Y0.)
(expect: feeds=X35,Y0/X40,Y26/X36,Y30/X10,Y30/X0,Y0 motion3=X40,Y5 motion7=X0,Y20 motions=8)
(expect: #100=1 status=completed)
(skip: limits@4 the chamfer is a motion of its block [line, N, F], so its two corners are inside one block: they take the planner's corner speed step, which the check allows only where the line changes)
