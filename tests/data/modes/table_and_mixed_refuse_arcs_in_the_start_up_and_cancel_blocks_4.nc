(fivex: --preset mixed-bc --dialect fanuc,syntec --allow-unbuilt)
G02 G41.2 D1 X10. Y10. R10. F100
(expect: alarm[fanuc]=PS0034 alarm[syntec]=COR-070)
