#100=1;
G90 G01 X2. F100;
#101=#5001;
M30;
(expect: #100=1 #101=2 status=completed)
