(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G91 G49
(expect: status=completed)
