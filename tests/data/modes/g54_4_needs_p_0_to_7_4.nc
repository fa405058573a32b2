(fivex: --preset mill3 --dialect fanuc,syntec --allow-unbuilt)
G54.4 P1.5
(twp WSE-01, TV-WSE-10)
(expect: alarm[fanuc]=PS0437 alarm[syntec]=COR-070)
