(fivex: --preset mill3 --allow-unbuilt)
G55
G54.1 P3
G91
G95
G54.4 P1
M30
(expect: status=completed)
