(fivex: --preset mill3 --allow-unbuilt)
G54.4 P1
G05.1 Q3
(twp §6.4, TV-WSE-15)
(expect: alarm=PS0437)
