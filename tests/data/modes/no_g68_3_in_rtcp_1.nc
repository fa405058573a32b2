(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G68.3
(syn SYN-07/23/33 [alarm not named: COR-100, decision]; FANUC: twp TWP-16 [PS5462])
(expect: alarm[fanuc]=PS5462 alarm[syntec]=COR-100)
