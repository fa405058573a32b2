(fivex: --preset head-bc --allow-unbuilt)
G43 H1
G43.4 H1
G49
(expect: alarm=PS5421)
