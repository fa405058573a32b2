(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G53 X0
(syn SYN-07/33, TV-17 [COR-118]; FANUC: G53 is not in the TCP list [tcp TCP-16])
(expect: alarm[fanuc]=PS5421 alarm[syntec]=COR-118)
