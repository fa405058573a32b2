G00 G01 X1. F100
#100=#4001
G01 G00 X2.
#101=#4001
M30
(expect: #100=1 #101=0 status=completed)
