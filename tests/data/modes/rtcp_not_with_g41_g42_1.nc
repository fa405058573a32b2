(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.4 H1
G41 D1
(syn SYN-07/08 [alarm not named: COR-100, decision]; FANUC allows it [tcp TCP-16])
(expect: alarm=COR-100)
