(fivex: --preset head-bc --allow-unbuilt)
G41.2 D1
G01 X10. F100
G02 X20. Y10. R10.
G01 G40
M30
(expect: status=completed)
