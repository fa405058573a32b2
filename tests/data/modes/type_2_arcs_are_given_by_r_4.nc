(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.5 H1
G00 X10. Y0 Z0
G02 X10. Y0 R10. F100
G01
G49
(expect: alarm[fanuc]=PS5421 alarm[syntec]=COR-100)
