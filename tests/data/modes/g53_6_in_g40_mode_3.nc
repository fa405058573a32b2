(fivex: --preset mill3 --allow-unbuilt)
G42 D1
G53.6 H1
G40
(expect: status=completed)
