(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G68.2 P3 Q3 I1. J0 K0
G69
(twp TWP-03/04, TV-TWP-11e; P outside 0..4 [decision]; Syntec's G68.2 has no P: COR-002, syn SYN-18)
(expect: alarm=COR-002 alarm_line=2)
