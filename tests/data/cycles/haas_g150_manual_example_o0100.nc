(fivex: --dialect haas)
(The 96-8000 manual's G150 example O0100 with its subroutine O0200, inch. Added: G20, the Z)
(moves a run needs, and G80 before the G150: fivex refuses G150 while a canned cycle is in)
(force. D02 holds a 5 mm tool radius here, not the example's 0.2 in.)
O0100 (G150 POCKET EXAMPLE)
G20
G58 G00 G90 X3.25 Y4.5 (STARTING HOLE POSITION)
T1 M06 (T1 CUTS ENTRY FOR END MILL)
G43 H01 Z1.
G83 R.1 Q0.5 Z-2. F20.
G80 G00 Z1.
T2 M06 (END MILL T2 CUTS POCKET)
G43 H02 Z1.
G150 G41 F15. D02 J0.35 K.01 Q0.5 R.1 X3.25 Y4.5 Z-2. P200
G40 X3.25 Y.45
G28
M30
O0200 (G150 POCKET SUBROUTINE)
G01 Y7.
X1.5
G03 Y5.25 R0.875
G01 Y2.25
G03 Y0.5 R0.875
G01 X5.
G03 Y2.25 R0.875
G01 Y5.25
G03 Y7. R0.875
G01 X3.25
M99 (RETURN FROM SUBROUTINE)
(Hand-computed: the tool radius + K is 5 + 0.254 = 5.254 mm. Motion 21 is the rapid to R, 0.1 in)
(= 2.54; 22 the plunge at the hole to R - Q = -0.4 in = -10.16; 23 the entry, straight up to the)
(outline pass at Y 7 in - 5.254 = 172.546; 24 along it to X 1.5 in = 38.1; 25 the lobe, radius)
(0.875 in - 5.254 = 16.971 about Y 6.125 in = 155.575, to Y 138.604; 26 the arc of radius 5.254)
(about the concave corner X1.5 Y5.25 in to X 38.1 + 5.254 = 43.354. Depths -10.16, -22.86,)
(-35.56, -48.26, -50.8; K: the pass at 5 mm at Z-2 in; then back to R over the hole; line 15)
(goes to X3.25 Y.45 in at R. The lobes' ends are known to 1e-6: their R arcs of 180 degrees put)
(the centre by a square root of a difference near zero. Line 16's G28 names no axis: every axis)
(goes to machine zero (96-8000 G28), and G28 cancels the tool length: G58 = 0, so work 0 0 0.)
(expect: status=completed motion21=X82.55,Y114.3,Z2.54 motion22=X82.55,Y114.3,Z-10.16 motion23=X82.55,Y172.546,Z-10.16 motion24=X38.1~1e-6,Y172.546 motion25=X38.1~1e-6,Y138.604~1e-9 motion26=X43.354,Y133.35 wX=0 wY=0 wZ=0)
(skip: limits@14 the pocket's moves are one block: their corners, the plunges at the hole and the turns between strokes, take the planner's corner speed step, which the check allows only where the line changes)
