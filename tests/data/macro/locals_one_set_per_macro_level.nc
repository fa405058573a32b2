#1=5.
#2=3.
G65 P9001 A7.
#102=#1
#103=#2
M30
O9001
#100=#1
#101=#2
#1=99.
M99
(In the macro: #1 is the argument, #2 [not given] is vacant.)
(Back in main: its own #1 and #2 are untouched.)
(expect: #100=7 #101=vacant #102=5 #103=3 status=completed)
