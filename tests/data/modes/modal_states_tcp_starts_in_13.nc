(fivex: --preset head-bc --allow-unbuilt)
G20
G93
G61
G59
G99
G43.4 H1
G49
M30
(expect: status=completed)
