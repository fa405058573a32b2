(fivex: --dialect fanuc,haas --workpiece block.json)
G90 G21 G54 G00 G43 H1 D1 Z10.
X-20. Y20.
Z-10.
G31 X20. F100.
#100=#5061
G00 X-20.
D0
G31 X20. F100.
#101=#5061
M30
(D1 has radius 5: a stylus ball of radius 5 whose lowest point is the tip, so its centre is at
 Z-5 and touches the face X0 when the tip is at X-5. With D0 the probe is a point: X0.)
(expect: #100=-5~1e-9 #101=0~1e-9 status=completed)
