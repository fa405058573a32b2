(fivex: --preset head-bc --allow-unbuilt)
G05.1 Q3
G43.4 H1
G49
G05.1 Q0
(expect: status=completed)
