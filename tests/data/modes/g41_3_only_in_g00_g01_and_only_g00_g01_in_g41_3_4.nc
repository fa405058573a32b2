(fivex: --preset head-bc --allow-unbuilt)
G01 F100
G41.3 D1
X10.
G00 Y10.
G40
M30
(expect: status=completed)
