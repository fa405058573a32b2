#1=1
#100=0
WHILE[#1LE10]DO1
#100=#100+#1
#1=#1+1
END1
M30
(expect: #100=55 status=completed)
