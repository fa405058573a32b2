(fivex: --preset mill3 --allow-unbuilt)
G68.2 P2 Q1 X0 Y0 Z0
G68.2 P2 Q2 X10. Y0 Z0
G68.2 P2 Q3 X0 Y10. Z10.
G69
M30
(expect: status=completed)
