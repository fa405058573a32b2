#1=0
WHILE[1EQ1]DO1
#1=#1+1
IF[#1GE5]GOTO 99
END1
N99 #100=#1
M30
(expect: #100=5 status=completed)
