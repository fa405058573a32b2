N1 G92 X-500. Y-500. G69 G17
N2 G68 X700. Y300. R60.
N3 G90 G01 X0 Y0 F200.
N4 G91 X1000.
N5 G02 Y1000. R1000.
N6 G03 X-1000. I-500. J-500.
N7 G01 Y-1000.
N8 G69 G90 X-500. Y-500.
M30
(N8: G69 in the block, then an ordinary absolute move.)
(expect: motions=6 motion6=X-500~1e-6,Y-500~1e-6)
(The manual's distances leave mill3's stroke: the run stops at N3 before it moves, the interpreter's motions above are all there.)
(expect: alarm=OT0510 alarm_line=3)
