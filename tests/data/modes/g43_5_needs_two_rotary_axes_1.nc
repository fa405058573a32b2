(fivex: --preset mill3 --allow-unbuilt)
G43.5 H1
(tcp TCP-08, TV-61)
(expect: alarm=PS5459)
