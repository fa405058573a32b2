M98 P20
#101=1
M30
O0020
#100=1
(expect: commons=100:1,101:1)
