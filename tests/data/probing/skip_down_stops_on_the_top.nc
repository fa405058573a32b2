(fivex: --dialect fanuc,haas --workpiece block.json)
G90 G21 G54 G00 G43 H1 Z10.
X25. Y20.
G31 Z-10. F100.
#100=#5063
G91 G01 Z2. F500.
#101=#5063
#102=#5003
M30
(block.json: a box 50 x 40 x 20 whose top is Z0 of G54, which is 0 on mill3, so the table frame
 is the workpiece system. No D: the probe is a point at the tip. The skip move stops at Z0;
 #5063 keeps the skip position after the next move, and the incremental move starts at the
 contact. M30 cancels the tool length on a Haas (96-8000, G49): its work Z after M30 is the
 nose's, 100 above.)
(expect: #100=0~1e-9 #101=0~1e-9 #102=2~1e-9 wZ[fanuc]=2~1e-9 wZ[haas]=102~1e-9 mZ=102~1e-9 status=completed)
