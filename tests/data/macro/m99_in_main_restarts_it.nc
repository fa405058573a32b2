#100=#100+1
IF[#100GE3]GOTO 9
M99
N9 M30
(expect: #100=3 status=completed)
