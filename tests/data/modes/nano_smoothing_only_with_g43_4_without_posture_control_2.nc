(fivex: --preset head-bc --allow-unbuilt)
G43.4 H1 P1
G05.1 Q3
(expect: alarm=PS5421)
