N5 #100=#100+1
IF[#100LT4]GOTO5
M30
(expect: #100=4 status=completed)
