(fivex: --dialect haas)
O00011 (M97 LOCAL SUBPROGRAM: THE MILL MANUAL'S EXAMPLE)
T1 M06
G00 G90 G54 X0 Y0 S1000 M03
G43 H01 Z1.
G01 Z0 F20.
M97 P1000 L5 (N1000 FIVE TIMES, THEN BACK HERE)
G00 G90 Z1.
M30
N1000 (THE LOCAL SUBPROGRAM)
G01 G91 Z-0.1
G90 X2.
G91 Z-0.1
G90 X0
M99
(Five passes of two 0.1 steps: the last reaches Z-1.0, then Z1. and M30; M99 returns to the
 block after the call, it never runs on from N1000.)
(M30 cancels the tool length (96-8000, G49): the work Z after it is the nose's, Z1 + 100.)
(expect: feeds=X0,Y0,Z0/X0,Y0,Z-0.1/X2,Y0,Z-0.1/X2,Y0,Z-0.2/X0,Y0,Z-0.2/X0,Y0,Z-0.3/X2,Y0,Z-0.3/X2,Y0,Z-0.4/X0,Y0,Z-0.4/X0,Y0,Z-0.5/X2,Y0,Z-0.5/X2,Y0,Z-0.6/X0,Y0,Z-0.6/X0,Y0,Z-0.7/X2,Y0,Z-0.7/X2,Y0,Z-0.8/X0,Y0,Z-0.8/X0,Y0,Z-0.9/X2,Y0,Z-0.9/X2,Y0,Z-1/X0,Y0,Z-1 wZ=101 status=completed)
