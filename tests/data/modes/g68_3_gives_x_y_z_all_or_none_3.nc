(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G68.3 Z0 R30.
(twp TWP-06, TV-TWP-15 [PS5457]; syn SYN-23, TV-21 [COR-141])
(expect: alarm[fanuc]=PS5457 alarm[syntec]=COR-141)
