(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G53.6 H0
(expect: alarm=MAR-407)
