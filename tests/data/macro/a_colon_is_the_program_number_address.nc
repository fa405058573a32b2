:1234
G65 P5678 A1.
M30
:5678
#100=#1+1
M99
(expect: #100=2 status=completed)
