#100=ATAN[-1]
M30
(expect: #100=315 status=completed)
