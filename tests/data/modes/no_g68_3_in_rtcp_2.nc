(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.4 H1
G49
G68.3
G69
(expect: status=completed)
