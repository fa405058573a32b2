#11005=50.
#10005=0.5
G90 G43 H5 G00 Z0
#100=#5023
M30
(expect: #100=50.5 status=completed)
