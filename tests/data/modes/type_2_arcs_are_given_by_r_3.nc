(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1
G02 X10. Y10. R10. F100
G01
G49
M30
(expect: status=completed)
