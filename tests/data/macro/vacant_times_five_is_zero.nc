#100=#1*5
M30
(expect: #100=0 status=completed)
