(fivex: --preset mill3 --allow-unbuilt)
G68.2 P3 Q3 I1. J0 K0
(twp TWP-03/04, TV-TWP-11e; P outside 0..4 [decision])
(expect: alarm=PS5457)
