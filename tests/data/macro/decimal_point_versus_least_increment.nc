G90 G00 X10
X10.
Y-2500
Z.5
M30
(expect: motion1=X0.01 motion2=X10 motion3=Y-2.5 motion4=Z0.5 status=completed)
