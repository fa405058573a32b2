#102=#102+1
N5 #100=#100+1
IF[#100GE3]GOTO 9
M99 P5
N9 M30
(expect: #102=1 #100=3 status=completed)
