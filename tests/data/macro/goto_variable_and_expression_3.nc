#1=30
GOTO#[1]
#100=1
N30 #101=30
M30
(expect: #101=30 status=completed)
