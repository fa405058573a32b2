(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G43.5 H1
(expect: alarm[fanuc]=PS5421 alarm[syntec]=COR-100)
