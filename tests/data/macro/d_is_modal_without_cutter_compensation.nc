D7
#100=#4107
G01 X10. F100
M30
(expect: #100=7 status=completed)
