(fivex: --preset head-bc --allow-unbuilt)
G02 G41.2 D1 X10. Y10. R10. F100
G40
M30
(expect: status=completed)
