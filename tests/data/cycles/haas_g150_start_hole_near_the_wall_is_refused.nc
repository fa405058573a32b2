(fivex: --dialect haas)
G00 G90 X3. Y10. Z5.
G150 X3. Y10. Z-3. R1. Q2.5 J6. P100 D1 F600.
M30
N100 G01 X0
Y20.
X30.
Y0
X0
Y10.
M99
(The start hole X3 is 3 mm from the wall x 0: the tool of radius 5 would cut it. The outline)
(runs clockwise, which nothing in the block contradicts (no G41). The block does nothing.)
(expect: alarm=746 alarm_line=3 wX=3 wY=10 wZ=5)
