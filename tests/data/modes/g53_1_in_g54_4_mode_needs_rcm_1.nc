(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G54.4 P1
G68.2 X0 Y0 Z0 I0 J0 K0
G53.1
(expect: alarm[fanuc]=PS5458 alarm[syntec]=COR-070)
