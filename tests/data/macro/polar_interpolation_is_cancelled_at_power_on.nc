(Group 21 starts in G13.1: #4021 is 13.1; it read 131 until the G codes got names.)
#100=#4021
M30
(expect: status=completed #100=13.1)
