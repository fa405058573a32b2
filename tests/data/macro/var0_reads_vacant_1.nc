#100=1
#100=#0
M30
(expect: #100=vacant status=completed)
