G66.1 P9400 A1.
X5.
A7. X2.
#103=1
G67
G90 G00 X9.
M30
O9400
#100=#100+1
#[110+#100]=#1
#[120+#100]=#24
M99
(The G66.1 block itself, `X5.` and `A7. X2.`: three calls; the macro statement and the)
(G67 block do not call.)
(expect: commons=100:3,103:1,111:1,113:7,122:5,123:2)
