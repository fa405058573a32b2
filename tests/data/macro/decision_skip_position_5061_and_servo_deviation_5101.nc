G90 G31 X10. F100
#100=#5061
#101=#5101
M30
(expect: #100=10 #101=0 status=completed)
