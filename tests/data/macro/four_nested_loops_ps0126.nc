(fivex: --dialect fanuc,syntec)
WHILE[1EQ1]DO1
WHILE[1EQ1]DO2
WHILE[1EQ1]DO3
WHILE[1EQ1]DO1
END1
END3
END2
END1
M30
(expect: alarm[fanuc]=PS0126 alarm[syntec]=COR-028)
