(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G05.1 Q3
G05.1 Q0
G49
(expect: status=completed)
