(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G10 L5000 P1 Q1
G10 L5000 P1
(expect: status=completed)
