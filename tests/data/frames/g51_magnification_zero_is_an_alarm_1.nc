(fivex: --dialect fanuc,syntec)
G51 X0 Y0 P0
M30
(expect: alarm[fanuc]=PS0142 alarm[syntec]=COR-045)
