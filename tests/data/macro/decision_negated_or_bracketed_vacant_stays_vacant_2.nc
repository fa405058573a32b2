#100=1
#100=[#1]
M30
(expect: #100=vacant status=completed)
