(fivex: --preset table-bc --dialect fanuc,syntec --allow-unbuilt)
G41.6 D1 I0 J0 K1.
G40
(expect: alarm[fanuc]=PS5460 alarm[syntec]=COR-070)
