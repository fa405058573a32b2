(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1 I0 J0 K1.
G49
M30
(expect: status=completed)
