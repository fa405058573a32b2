(fivex: --dialect haas)
G00 G20 G90 X0 Y0 Z0.5
G187 P3 E0.0125
G01 Z0 F50.
X2.
Y2.
X0
Y0
#100 = #5021
G00 Z0.5
M30
(The example of Haas's "Advances in Motion Control" page, G187 P3 E0.0125: a maximum corner)
(rounding of 0.0125 in = 0.3175 mm. The square's three corners at X2 Y0, X2 Y2, X0 Y2 turn by 90)
(degrees: each arc leaves the line d = E / tan 22.5 = 0.0302 in before the corner; the corner)
(after the plunge [Z0.5 to Z0, then X2] is 90 degrees too, rounded the same. The macro statement moves what is held first: the last corner)
(at X0 Y0 stays exact and #5021 reads the programmed end, 0 in X [the machine position in mm].)
(expect: status=completed wX=0 wY=0 wZ=12.7 #100=0)
