(fivex: --preset mill3 --allow-unbuilt)
G54.4 P1
G54.4 P0
G54.4 P2
M30
(expect: status=completed)
