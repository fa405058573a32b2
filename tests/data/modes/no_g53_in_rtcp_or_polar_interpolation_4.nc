(fivex: --preset mill3 --allow-unbuilt)
G12.1
G53 X0
G13.1
M30
(expect: status=completed)
