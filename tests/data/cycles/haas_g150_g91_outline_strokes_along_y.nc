(fivex: --dialect haas)
G00 G90 X20. Y10. Z5.
G150 X20. Y10. Z-3. R1. Q2.5 I6. P2000 D1 F600.
G00 Z10.
M30
O2000 (the outline in G91: a 40 x 24 rectangle, its first move to the right wall)
G91 G01 X20.
Y14.
X-40.
Y-24.
X40.
Y10.
G90
M99
(D1: radius 5, no K: the outline pass is the rectangle x 5..35, y 5..19. I6: strokes along Y)
(every 30 / ceil(30 / 6) = 6 in X, at x 29, 23, 17, 11, from the side of the pass's start X35)
(Y10. Depths R - Q = -1.5, then Z -3. Per depth: the plunge, the entry to X35 Y10, the pass)
(5 moves, down the wall to X35 Y5 and along to X29 (11 + 15 < 9 + 6 + 9 the other way), 4)
(strokes and 3 links along the pass, back along the bottom to X35 Y5 and up to X35 Y10, to the)
(hole: 19 motions. With the G00 of line 2, the rapid to R, the one back to R and line 4: 42.)
(expect: motions=42 motion2=X20,Y10,Z1 motion3=X20,Y10,Z-1.5 motion4=X35,Y10 motion5=X35,Y19 motion10=X35,Y5 motion11=X29,Y5 motion12=X29,Y19 motion13=X23,Y19 motion18=X11,Y5 motion20=X35,Y10 motion21=X20,Y10,Z-1.5 motion22=X20,Y10,Z-3 wX=20 wY=10 wZ=10)
(skip: limits@3 the pocket's moves are one block: their corners, the plunges at the hole and the turns between strokes, take the planner's corner speed step, which the check allows only where the line changes)
