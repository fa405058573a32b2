G10 L2 P1 X12. Y-3.
G10 L2 P6 Z7.
G10 L2 P0 X0.5
#100=#5221
#101=#5222
#102=#5323
#103=#5201
G91 G10 L2 P1 X1.
#104=#5221
M30
(expect: commons=100:12,101:-3,102:7,103:0.5,104:13)
(G10 does not move.)
(expect: motions=0)
