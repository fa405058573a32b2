(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G68.2 P2 X0 Y0 Z0
G69
(twp TWP-03/04, TV-TWP-11e; P outside 0..4 [decision])
(expect: status=completed)
