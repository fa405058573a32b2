(fivex: --preset head-bc --dialect syntec)
N1 G54 G90 G00 B0. C0.
N2 C45.
N3 B90.
N4 G68.3 P1 X0. Y0. Z0.
N5 G01 X0 Y10. Z0 F1000
N6 G69
N7 M30
(Syntec TV-08: G68.3 P1 takes the feature frame from the rotary axes, Rz45 Ry90 on this right-handed head, so feature Y10 is G54 -7.071068, 7.071068, 0 for the nose; with the B pivot 150 above it and the tool along 0.707107, 0.707107, 0 the carriage is at the nose - 150 z + 150 t: X = -7.071068 + 106.066017, Y = 7.071068 + 106.066017)
(expect: status=completed mX=98.99494936611666 mY=113.13708498984761 mZ=-150 mB=90 mC=45)
(skip: tip@4 a rotary move without tool centre point control swings the tip off the commanded point)
