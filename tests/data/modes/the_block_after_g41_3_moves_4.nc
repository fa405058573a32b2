(fivex: --preset head-bc --allow-unbuilt)
G41.3 D1
X10.
F100
G40
M30
(expect: status=completed)
