(fivex: --preset mixed-bc --allow-unbuilt)
G41.6 D1 I0 J0 K1.
G40
M30
(expect: status=completed)
