(fivex: --dialect haas)
G90 G21 G54 G00 X0 Y30.
N10 G01 X20. Y30. ,C3. F500.
N20 Y0
M30
(helmancnc.com, "Haas corner rounding and chamfering": N10 G01 X20 Y30 ,C3 [mm here]. From)
(X0 Y30 the corner is X20 Y30; the next line goes down to Y0. The chamfer runs from X17 Y30 to)
(X20 Y27: 3 along each line from the corner.)
(expect: feeds=X17,Y30/X20,Y27/X20,Y0 motions=4 status=completed)
(skip: limits@3 the chamfer is a motion of its block [line, N, F], so its two corners are inside one block: they take the planner's corner speed step, which the check allows only where the line changes)
