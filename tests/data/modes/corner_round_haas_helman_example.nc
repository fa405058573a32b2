(fivex: --dialect haas)
G90 G21 G54 G00 X0 Y30.
N10 G01 X20. Y30. ,R3. F500.
N20 Y0
M30
(helmancnc.com, "Haas corner rounding and chamfering": N10 G01 X20 Y30 ,R3. A right angle: the)
(arc's tangent points are 3 from the corner, X17 Y30 and X20 Y27; turning right [+X to -Y] it is)
(clockwise about X17 Y27, radius 3, -90 degrees.)
(expect: feeds=X17,Y30/X20,Y0 motion3=X20,Y27 motions=4 status=completed)
