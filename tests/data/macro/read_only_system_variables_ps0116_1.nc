(fivex: --dialect fanuc,syntec)
#4001=1
M30
(Syntec's #4001–#5500 are user parameters: refused, docs/dialects.md.)
(expect: alarm[fanuc]=PS0116 alarm[syntec]=COR-016)
