#3001=0
G90 G01 X100. F6000
#100=#3001
M30
(expect: #100=0 status=completed)
