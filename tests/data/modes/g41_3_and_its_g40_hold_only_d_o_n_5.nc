(fivex: --preset head-bc --allow-unbuilt)
N1 G41.3 D1
X10.
N3 G40
M30
(expect: status=completed)
