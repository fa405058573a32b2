(fivex: --dialect haas)
G00 G90 X50. Y50. Z1.
G91 G13 I12. D1 Z-2. L3 F300.
G90 G00 Z10.
M30
(G91 with L: the Z increment cut L times, each a plunge at the centre, out, the circle)
(of 12 - 5 = 7 mm, back to the centre: 1 rapid + 3 x 4 + 1 rapid motions.)
(expect: status=completed feeds=X50,Y50,Z-1/X50,Y50,Z-3/X50,Y50,Z-5 motions=14 wX=50 wY=50 wZ=10)
(skip: limits@3 the pocket's moves are one block: their corners, the plunge into the first half circle and the reversals between passes, take the planner's corner speed step, which the check allows only where the line changes)
