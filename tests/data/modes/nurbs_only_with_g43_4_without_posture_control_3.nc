(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G06.2 P2 K1. F100
K1. X1.
K2.
K2.
G01
G49
(Syntec refuses G06.2 as not built; with --allow-unbuilt it runs FANUC's format. In G43.5)
(K is also the tool vector's: K1. keeps the tool along +Z.)
(expect: status=completed)
