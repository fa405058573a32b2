(fivex: --preset table-bc --allow-unbuilt)
G43.5 H1 I0 J0 K1.
(tcp TCP-08, TV-58/59)
(expect: alarm=PS5421)
