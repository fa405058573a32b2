(fivex: --dialect fanuc,syntec)
#1=1000
G#1
M30
(expect: alarm[fanuc]=PS0010 alarm[syntec]=COR-070)
