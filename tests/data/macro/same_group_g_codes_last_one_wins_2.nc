G90 G00 X5.
G90 G91 X1.
#100=#4003
#101=#5001
M30
(expect: #100=91 #101=6 status=completed)
