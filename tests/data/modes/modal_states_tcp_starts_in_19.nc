(fivex: --preset head-bc --allow-unbuilt)
G44 H1
G49
G43.4 H1
G49
M30
(tcp TCP-15 [§2.3.2]: G49 is in the list [a TCP-16 code], G43/G44 are not: TCP never)
(starts over tool length compensation, only after its G49.)
(expect: status=completed)
