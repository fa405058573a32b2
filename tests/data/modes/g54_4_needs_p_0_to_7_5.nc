(fivex: --preset mill3 --allow-unbuilt)
G54.4 P7
G54.4 P0
M30
(expect: status=completed)
