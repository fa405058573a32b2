#100=0
GOTO 10
#100=1
N10 #101=2
M30
(expect: #100=0 #101=2 status=completed)
