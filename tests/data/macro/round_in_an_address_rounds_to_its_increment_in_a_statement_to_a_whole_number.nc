#1=ROUND[1.2346]
#100=#1
M30
(expect: #100=1 status=completed)
