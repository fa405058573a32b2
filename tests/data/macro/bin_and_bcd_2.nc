#100=BCD[1234]
M30
(expect: #100=4660 status=completed)
