#100=1;
G90 G01 X2. F100;
#101=#5001;
M30;
(expect: motions=1 motion1=X2 status=completed)
