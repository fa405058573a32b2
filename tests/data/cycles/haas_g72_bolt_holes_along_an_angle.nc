(fivex: --dialect haas)
G00 G90 X10. Y10. Z10.
G98 G81 Z-5. R2. F300. L0
G72 I5. J90. L3
G80
M30
(The first hole at the block's point, the others every 5 mm along 90 degrees.)
(expect: status=completed feeds=X10,Y10,Z-5/X10,Y15,Z-5/X10,Y20,Z-5 wX=10 wY=20 wZ=10)
