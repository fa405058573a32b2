(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G01 X10. F100
G02 X20. Y10. R10.
G04 P1
G91 G01 X1.
G90
G41 D1 X1.
G40 X0
G93
G94 F100
G49
M30
(G94 F100: after G93 the G49 block's move in G01 needs a new F, PS0011)
(expect: status=completed)
