(fivex: --dialect fanuc,haas --workpiece pocket.json)
G90 G21 G17 G40 G80 G54
G00 X20. Y12.
G43 H1 D1 Z5.
G65 P9102 Z-10.
G00 Z5.
X0 Y0
M30
O9102
(Finds a rectangular pocket's centre from where the probe stands over it at the depth Z #26)
(and moves G54 there: four skip moves, each from the start point, a back-off after each.)
#1=#5001
#2=#5002
G01 Z#26 F500.
G31 X[#1+50.] F100.
#11=#5061
G01 X#1 F500.
G31 X[#1-50.] F100.
#12=#5061
G01 X#1 F500.
G31 Y[#2+50.] F100.
#13=#5062
G01 Y#2 F500.
G31 Y[#2-50.] F100.
#14=#5062
G01 Y#2 F500.
#130=[#11+#12]/2
#131=[#13+#14]/2
#132=#11-#12
#5221=#5221+#130
#5222=#5222+#131
M99
(pocket.json: the pocket is X10–40, Y5–25, 15 deep. The ball [radius 5] touches the walls with
 its tip at X35, X15, Y20, Y10: centre X25 Y15, and the tip's travel between the X walls is
 the width 30 less the ball's diameter. G54 moves to the centre: X0 Y0 is then machine X25 Y15.)
(expect: #130=25~1e-9 #131=15~1e-9 #132=20~1e-9 #5221=25~1e-9 #5222=15~1e-9 wX=0~1e-9 wY=0~1e-9 mX=25~1e-9 mY=15~1e-9 status=completed)
