(fivex: --preset mixed-bc --allow-unbuilt)
G42.2 D1
G40
M30
(expect: status=completed)
