(fivex: --dialect haas)
G90 G21 G54 G00 X0 Y30.
G101 X0.
N10 G01 X20. Y30. ,R3. F500.
N20 Y0
G100
M30
(G101 X mirrors X about zero: from X0 Y30 the corner is X-20 Y30, then down to X-20 Y0. The)
(arc is built on the mirrored lines: tangent points X-17 Y30 and X-20 Y27, about X-17 Y27, and)
(it turns the other way than without the mirror - counter-clockwise [G03], as G101 turns a G02.)
(expect: feeds=X-17,Y30/X-20,Y0 motion3=X-20,Y27 motions=4 status=completed)
