#100=FIX[3]
M30
(expect: #100=3 status=completed)
