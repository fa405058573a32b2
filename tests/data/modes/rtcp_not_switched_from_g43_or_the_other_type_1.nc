(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43 H1
G43.4 H1
(syn SYN-07/08 [alarm not named: COR-100, decision]; FANUC: G43.5 is not in the TCP list,)
(and G43/G44 are not among the modal states TCP may start in [TCP-15])
(expect: alarm=COR-100)
