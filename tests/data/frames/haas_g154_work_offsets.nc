(fivex: --dialect haas)
G10 L20 P5 X10. Y20. Z0
G10 L20 P1 X-5. Y0 Z0
#14081=30. (G154 P5 X)
G90 G154 P5 G00 X1. Y1.
#100=#5021
#101=#5022
#102=#4012
G110 X1. Y1. (G110 IS G154 P1)
#103=#5021
#104=#7001 (G110 X)
#105=#14001 (G154 P1 X)
M30
(G154 P5 X was set to 10 by G10 L20, then to 30 by #14081: X1 is machine 31, Y1 is 21.)
(expect: #100=31 #101=21 #102=154 #103=-4 #104=-5 #105=-5 status=completed)
