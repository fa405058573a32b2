(fivex: --preset head-bc --allow-unbuilt)
G42 D1
G43.5 H1
G40
G49
M30
(syn SYN-07/08 [alarm not named: COR-100, decision]; FANUC allows it [tcp TCP-16])
(expect: status=completed)
