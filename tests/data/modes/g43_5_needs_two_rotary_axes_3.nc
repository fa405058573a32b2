(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1
G49
(expect: status=completed)
