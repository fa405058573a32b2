(fivex: --preset mill3 --allow-unbuilt)
G54.4 P1
G01 X10. F100
G05.1 Q1
G43 H1
G49
G81 X0 Y0 Z-1. R1.
G80
G54.4 P0
G61
M30
(expect: status=completed)
