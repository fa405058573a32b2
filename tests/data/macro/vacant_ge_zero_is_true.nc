IF[#1GE0]THEN#100=1
M30
(expect: #100=1 status=completed)
