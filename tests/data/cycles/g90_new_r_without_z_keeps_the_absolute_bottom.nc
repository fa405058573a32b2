G90 G00 X0 Y0 Z50.
G99 G81 X10. R5. Z-10. F300.
X20. R10.
G80
M30
(expect: feeds=X10,Y0,Z-10/X20,Y0,Z-10 status=completed)
