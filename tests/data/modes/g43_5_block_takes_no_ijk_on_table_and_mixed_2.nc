(fivex: --preset mixed-bc --allow-unbuilt)
G43.5 H1 I0 J0 K1.
(expect: alarm=PS5421)
