G65 P9200 L3 A1.
M30
O9200
#1=#1+1
#100=#100+#1
#101=#101+1
M99
(Each repetition starts with #1 = 1 again: 3 × 2 = 6 [not 2 + 3 + 4 = 9].)
(expect: #100=6 #101=3 status=completed)
