(fivex: --dialect fanuc,syntec)
#1000=1
(Syntec's #1000 is its interpolation mode, not an input: refused, docs/dialects.md.)
(expect: alarm[fanuc]=PS0116 alarm[syntec]=COR-016)
