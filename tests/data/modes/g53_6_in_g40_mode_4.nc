(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G41 D1
G40
G53.6 H1
(expect: status=completed)
