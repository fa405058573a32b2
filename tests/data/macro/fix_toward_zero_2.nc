#100=FIX[-1.7]
M30
(expect: #100=-1 status=completed)
