#2=5.
#2=#1
IF[#2EQ#0]THEN#100=1
IF[#2EQ0]THEN#101=1
#102=#2
M30
(expect: #100=1 #101=vacant #102=vacant status=completed)
