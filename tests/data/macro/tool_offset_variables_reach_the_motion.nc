#11005=50.
#10005=0.5
G90 G43 H5 G00 Z0
#100=#5023
M30
(expect: #100=50.5)
(skip: tip its only motion is the G43 block, which moves the machine by the tool length while the commanded point moves from where it was)
