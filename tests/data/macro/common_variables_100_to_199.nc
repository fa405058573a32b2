G65 P9000
#101=#100+1
M30
O9000
#100=4.
M99
(They are shared across levels.)
(expect: #101=5 status=completed)
