(fivex: --dialect fanuc,syntec)
G17 G68 X0 Y0 R30.
G18 G02 X10. Z0 R5. F100.
M30
(expect: alarm[fanuc]=PS0144 alarm[syntec]=COR-035)
