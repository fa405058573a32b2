(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.5 H1
G01 X10. B30. F100
(expect: alarm[fanuc]=PS5421 alarm[syntec]=COR-158)
