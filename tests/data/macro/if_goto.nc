#1=3
IF[#1GT2]GOTO 10
#100=1
N10 IF[#1GT5]GOTO 20
#101=1
N20 M30
(expect: #100=vacant #101=1 status=completed)
