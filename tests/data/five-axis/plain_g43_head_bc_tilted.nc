(fivex: --preset head-bc --dialect fanuc,syntec)
N1 G90 G54 G00 X0 Y0 Z200. B30. C0
N2 G43 H1 Z200.
N3 G01 X10. Y0 Z10. F3000
N4 M30
(Plain G43 adds the 100 mm length along machine Z whatever the head's angle: the carriage goes to 10, 0, 110; the tilted tool's tip is elsewhere, and the tip invariant holds it to the commanded path carried rigidly. The G43 block names Z, as posts write it: a bare G43 moves nothing on a FANUC with TOS = 1, and its length would then first show in the G01)
(expect: status=completed wX=10 wY=0 wZ=10 mX=10 mY=0 mZ=110 mB=30 mC=0)
(skip: tip@2 the rapid turns B without tool centre point control, which swings the tip off the commanded point)
