G90 G00 X0 Y0
G52 X10. Y20.
G00 X0 Y0
G92 X0
G52 X0
#100=#5041
#101=#5021
G00 Y0
#102=#5022
M30
(Y was not named: its local origin [20] stays.)
(expect: #100=0 #101=10 #102=20 status=completed)
