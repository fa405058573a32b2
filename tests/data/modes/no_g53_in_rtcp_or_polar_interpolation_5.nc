(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.4 H1
G49
G53 X0
(expect: status=completed)
