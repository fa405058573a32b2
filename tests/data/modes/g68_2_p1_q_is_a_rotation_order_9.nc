(fivex: --preset mill3 --allow-unbuilt)
G68.2 P1 Q321 X0 Y0 Z0 I0 J0 K0
G69
G68.2 P1 X0 Y0 Z0 I0 J0 K0
G69
M30
(expect: status=completed)
