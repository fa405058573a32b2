(fivex: --preset mill3 --dialect fanuc,syntec --allow-unbuilt)
G68 X0 Y0 R10.
G54.4 P1
(twp §6.3, TV-WSE-16; decision: power-on codes [G22 here] count as allowed)
(expect: alarm[fanuc]=PS0439 alarm[syntec]=COR-070)
