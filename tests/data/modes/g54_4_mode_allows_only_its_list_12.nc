(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G54.4 P1
G05.1 Q3
(twp §6.4, TV-WSE-15)
([on a Syntec machine with a mechanism: G68.3 needs one, COR-154])
(expect: alarm=COR-070)
