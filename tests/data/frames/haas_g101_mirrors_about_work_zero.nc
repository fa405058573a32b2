(fivex: --dialect haas)
G90 G21 G54 G00 X0 Y0
G101 X5.
G01 X10. Y5. F500.
G100
G01 X10. Y5.
G101 Y0
G01 X3. Y4.
G100 X0
G01 X1. Y1.
G101 X0 Y0
G02 X-1. Y-1. R1.
G100
G01 X2. Y2.
M30
(96-8000, G101: the axes named are mirrored "around your work coordinate zero point", whatever)
(the value [X5. mirrors X about 0]; G100 with axes cancels those, alone all of them. Both axes)
(mirrored keep G02 a G02 [one axis alone would reverse it]: from X1 Y-1, programmed X-1 Y1, the)
(arc to the programmed X-1 Y-1 runs clockwise from X1 Y-1 to X1 Y1 about X1 Y0.)
(expect: feeds=X-10,Y5/X10,Y5/X3,Y-4/X1,Y-1/X2,Y2 wX=2 wY=2 status=completed)
