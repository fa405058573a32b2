(fivex: --preset head-bc --dialect syntec)
G90 G01 X0 Y0 Z0 F1000
G05 P10000 X0 Y0 Z0 B1. C1.
X1. B1.
X2. Y0.1 B2.
G05 P0
G05 P10000
X3.
G05 P0
M30
(the two forms, then P0: the 5-axis form and the linear axes alone)
(expect: status=completed wX=3 wY=0.1 wB=2)
(skip: tip@4 B turns without tool centre point control - HPCC is not allowed under it - which swings the tip off the commanded point)
(skip: tip@5 B turns without tool centre point control, which swings the tip off the commanded point)
