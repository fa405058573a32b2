G90 G00 X0 Y0 Z20.
G99 G81 X10. R5. Z-7. K0 F300.
X30.
G80
M30
(expect: feeds=X30,Y0,Z-7 status=completed)
