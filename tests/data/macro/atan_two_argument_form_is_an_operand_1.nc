#100=ATAN[1]/[1]*2
M30
(ATAN[a]/[b] is one operand: the division is part of it, then *2 applies.)
(expect: #100=90 status=completed)
