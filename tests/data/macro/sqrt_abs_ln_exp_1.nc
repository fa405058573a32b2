#100=SQRT[16]
M30
(expect: #100=4 status=completed)
