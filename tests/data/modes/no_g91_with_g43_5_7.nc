(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
X10.
G49
G91 X1.
G90
(expect: status=completed)
