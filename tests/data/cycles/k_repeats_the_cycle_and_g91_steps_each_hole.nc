G90 G00 X0 Y0 Z20.
G91 G99 G81 X10. R-15. Z-7. K3 F300.
G80
M30
(expect: feeds=X10,Y0,Z-2/X20,Y0,Z-2/X30,Y0,Z-2 status=completed)
