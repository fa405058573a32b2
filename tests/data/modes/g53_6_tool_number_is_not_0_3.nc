(fivex: --preset mill3 --allow-unbuilt)
G53.6
G53.6 H0
(expect: status=completed)
