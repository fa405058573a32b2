G51 X0 Y0 I2000 J1000
G00 X10. Y0
G02 X0 Y-10. I-10. F100.
M30
(X×2, Y×1: from [20, 0] a quarter G02 X0 Y-10 I-10 ends at [0, -10] with the center [0, 0]:)
(radii 20 and 10 → PS0020 [FANUC interpolates a spiral there; this engine alarms].)
(expect: alarm=PS0020)
