(fivex: --preset table-bc --dialect fanuc,syntec --allow-unbuilt)
G41.2 D1
G01 X10. F100
G02 X20. Y10. R10.
(expect: alarm[fanuc]=PS5460 alarm[syntec]=COR-070)
