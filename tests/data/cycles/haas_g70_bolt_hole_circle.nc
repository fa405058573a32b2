(fivex: --dialect haas)
G00 G90 X0 Y0 Z10.
G98 G81 Z-5. R2. F300. L0
G70 I20. J0 L4
G80
M30
(L0 keeps the cycle from drilling the centre; four holes every 90 degrees from J0 at the)
(3 o'clock position, counter-clockwise; the tool ends over the last one at the initial level.)
(expect: status=completed feeds=X20,Y0,Z-5/X0,Y20,Z-5/X-20,Y0,Z-5/X0,Y-20,Z-5 wX=0 wY=-20 wZ=10)
