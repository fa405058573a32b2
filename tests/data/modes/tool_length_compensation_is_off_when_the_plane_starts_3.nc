(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G68.2 X0 Y0 Z0 I0 J0 K0
(twp TWP-16, TV-TWP-21 [PS5462]; syn SYN-18 [alarm not named: COR-100, decision])
(expect: alarm[fanuc]=PS5462 alarm[syntec]=COR-100)
