#1=0
WHILE[#1LT3]DO1
#100=#100+1
#1=#1+1
END1
#1=0
WHILE[#1LT4]DO1
#101=#101+1
#1=#1+1
END1
M30
(expect: #100=3 #101=4 status=completed)
