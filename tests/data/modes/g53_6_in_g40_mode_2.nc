(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G42 D1 G53.6 H1
(expect: alarm=MAR-406)
