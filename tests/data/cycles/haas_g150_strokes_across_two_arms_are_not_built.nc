(fivex: --dialect haas)
G00 G90 X15. Y-8. Z5.
G150 G41 X15. Y-8. Z-3. R1. Q2.5 J6. P100 D1 F600.
M30
N100 G01 Y-15.
X32.
Y15.
X20.
Y0
X12.
Y15.
X0
Y-15.
X15.
M99
(A U: base y -15..0, arms x 0..12 and 20..32. Strokes along X (J) above the base cross both)
(arms: each is two pieces, whose order fivex does not build: 310. With I the same U is cut,)
(haas_cycles.rs g150_refusals.)
(expect: alarm=310 alarm_line=3 wX=15 wY=-8 wZ=5)
