G17 G18
#100=#4002
M30
(Group 02: G17 G18 → G18.)
(expect: #100=18 status=completed)
