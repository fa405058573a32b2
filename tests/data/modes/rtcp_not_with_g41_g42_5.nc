(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G41 D1
G40
G43.4 H1
G49
(expect: status=completed)
