(fivex: --dialect fanuc,haas)
#100=0
G65 P3000 L3 A1.
M30
O3000
#1=#1+1
#100=#100+#1
M99
(FANUC sets the arguments again for each repetition: #1 = 2 each time, #100 = 6. Haas sets them
 on the first only and keeps the locals: #1 = 2, 3, 4, #100 = 9.)
(expect: #100[fanuc]=6 #100[haas]=9 status=completed)
