(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G53.6 H1
G49
G53.6
(expect: status=completed)
