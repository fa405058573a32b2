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
(expect: motions=1 motion1=X9 status=completed)
