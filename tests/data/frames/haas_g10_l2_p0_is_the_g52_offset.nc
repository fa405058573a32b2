(fivex: --dialect fanuc,haas)
G10 L2 P0 X5.
G00 X1.
#100=#5201
#101=#5021
M30
(Haas: G10 L2 P0 sets the G52 offset, #5201. FANUC: P0 is the external work offset, which is
 #5201 there too. Both shift the work system by 5.)
(expect: #100=5 #101=6 status=completed)
