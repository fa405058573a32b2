(fivex: --preset head-bc --dialect fanuc,syntec --allow-unbuilt)
G43.4 H1
G02 B10. F100
(tcp TCP-06/07/10 [alarm not named: PS5421, decision; FANUC only])
(expect: alarm[fanuc]=PS5421 alarm[syntec]=COR-017)
