(fivex: --dialect haas)
G00 G90 X100. Y50. Z10.
G99 G81 Z-5. R2. F300. L0
G71 I20. J180. K-90. L3
G80
M30
(Three holes from 180 degrees every -90 degrees, clockwise: 180, 90, 0, about X100 Y50;)
(G99: the tool ends at the R level over the last hole.)
(expect: status=completed feeds=X80,Y50,Z-5/X100,Y70,Z-5/X120,Y50,Z-5 wX=120 wY=50 wZ=2)
