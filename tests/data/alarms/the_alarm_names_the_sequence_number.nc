N10 G00 X1.
N20 G01 X2.
(expect: alarm=PS0011 alarm_line=2 alarm_n=20)
