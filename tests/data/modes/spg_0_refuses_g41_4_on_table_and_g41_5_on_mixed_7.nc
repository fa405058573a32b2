(fivex: --preset mixed-bc --allow-unbuilt)
G42.2 D1
G40
(expect: status=completed)
