#1=0
WHILE[#1LT3]DO1
#1=#1+1
GOTO 10
#100=99
N10 #101=#101+1
END1
M30
(expect: #100=vacant #101=3 status=completed)
