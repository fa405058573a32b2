(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G02 X10. Y10. R10. K1. F100
G01
G49
(expect: status=completed)
