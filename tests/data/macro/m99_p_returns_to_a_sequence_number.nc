M98 P20
#100=1
N50 #101=2
M30
O0020
M99 P50
(expect: #100=vacant #101=2 status=completed)
