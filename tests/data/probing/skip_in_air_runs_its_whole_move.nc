(fivex: --dialect fanuc,haas --workpiece block.json)
G90 G21 G54 G00 G43 H1 Z10.
X60. Y20.
G31 Z-10. F100.
#100=#5063
G31 X70. F100.
#101=#5061
#102=#5063
M30
(Beside the box: nothing is touched, the move ends at its end point, which #5061… hold. M30)
(cancels the tool length on a Haas, 96-8000 G49: its work Z after M30 is the nose's, 100 above.)
(expect: #100=-10 #101=70 #102=-10 wX=70 wZ[fanuc]=-10 wZ[haas]=90 status=completed)
