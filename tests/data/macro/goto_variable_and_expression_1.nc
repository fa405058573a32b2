#1=20
GOTO#1
N10 #100=10
N20 #101=20
M30
(expect: #100=vacant #101=20 status=completed)
