(fivex: --preset head-bc --dialect fanuc,syntec)
G43.4 H1
G05 P10000
(syn SYN-07/08/09, TV-16 [COR-140]; FANUC: G05 is not in the TCP list)
(expect: alarm[fanuc]=PS5421 alarm[syntec]=COR-140)
