#100=#3002
G04 X360.
#101=#3002
M30
(expect: #100=0 #101=0.1 status=completed)
