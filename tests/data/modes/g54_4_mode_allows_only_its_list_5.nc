(fivex: --preset mill3 --allow-unbuilt)
G54.4 P1
G52 X1.
(twp §6.4, TV-WSE-15)
(expect: alarm=PS0437)
