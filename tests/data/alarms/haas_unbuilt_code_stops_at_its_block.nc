(fivex: --dialect haas)
G00 X1.
G47 P0 X0 Y0 I0 J0.5 R0.05 Z-0.005 F15. (TEXT ENGRAVING: NOT BUILT IN FIVEX)
G00 X5.
M30
(expect: alarm=310 alarm_line=3 wX=1)
