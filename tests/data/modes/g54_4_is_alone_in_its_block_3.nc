(fivex: --preset mill3 --allow-unbuilt)
G90
G54.4 P1
X10.
G54.4 P0
M30
(expect: status=completed)
