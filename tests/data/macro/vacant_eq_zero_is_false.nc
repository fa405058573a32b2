#100=0
IF[#1EQ0]THEN#100=1
M30
(expect: #100=0 status=completed)
