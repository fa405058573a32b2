(fivex: --preset mixed-bc --dialect fanuc,syntec --allow-unbuilt)
G41.2 D1
G01 X10. F100
G03 X0 Y0 R10. D0
(expect: alarm[fanuc]=PS0034 alarm[syntec]=COR-070)
