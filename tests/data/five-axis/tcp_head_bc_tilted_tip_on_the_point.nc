(fivex: --preset head-bc --dialect fanuc,syntec)
N1 G90 G54 G00 X0 Y0 Z200. B30. C0
N2 G43.4 H1
N3 G01 X10. Y0 Z10. F3000
N4 M30
(Under TCP the tip is at the programmed 10, 0, 10 with the head at B30: the B pivot is 250 up the tool from the tip [150 pivot to nose, 100 tool], at 10 + 250 sin30, 0, 10 + 250 cos30 = 135, 0, 226.506351; the carriage 150 below it)
(expect: status=completed wX=10 wY=0 wZ=10 mX=135 mY=0 mZ=76.50635094610965 mB=30 mC=0)
(skip: tip@2 the rapid turns B without tool centre point control, which swings the tip off the commanded point)
