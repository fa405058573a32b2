(fivex: --dialect fanuc,haas)
G00 X1.
M97 P10
M30
N10 #100=1
X5.
M99
(FANUC has no M97: an M code passed to the machine, and the program ends at M30. Haas calls N10.)
(expect: #100[fanuc]=vacant #100[haas]=1 wX[fanuc]=1 wX[haas]=5 status=completed)
