#1=0
WHILE[#2GT#1]DO1
#100=1
END1
M30
(A vacant WHILE condition value is false, a zero one too.)
(expect: #100=vacant status=completed)
