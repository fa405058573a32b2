(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43 H1
G49
G43.4 H1
G43.4 H2
G49
(expect: status=completed)
