(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1
G00 X10. Y0 Z0
G02 X10. Y0 I-10. F100
G01
G49
M30
(expect: status=completed)
