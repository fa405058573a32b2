#3006=1 (CHECK PART)
#100=1
M30
(expect: commons=100:1)
