G90 G00 X0 Y0 Z50.
G91 G99 G81 X10. R-45. Z-15. F300.
X10. R-40.
G80
M30
(expect: feeds=X10,Y0,Z-10/X20,Y0,Z-5 status=completed)
