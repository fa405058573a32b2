(fivex: --dialect fanuc,syntec)
#100=#3021
M30
(The NGC's cycle start timer is no FANUC or Syntec variable.)
(expect: alarm[fanuc]=PS0115 alarm[syntec]=COR-016 alarm_line=2)
