#1=5
GOTO[#1*2]
#100=1
N10 #101=10
M30
(expect: #100=vacant #101=10 status=completed)
