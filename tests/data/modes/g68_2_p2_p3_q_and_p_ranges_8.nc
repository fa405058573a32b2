(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G68.2 P5 X0
G69
(twp TWP-03/04, TV-TWP-11e; P outside 0..4 [decision])
(expect: status=completed)
