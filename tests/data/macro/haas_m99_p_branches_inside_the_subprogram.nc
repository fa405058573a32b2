(fivex: --dialect fanuc,haas)
M98 P20
#102=1
M30
N5 #100=5 (THE CALLER'S N5)
M30
O0020
#101=1
M99 P5
N5 #101=2
M99
(FANUC: M99 P5 returns to the caller's N5. The Haas mill manual: M99 P branches to N5 of the
 subprogram itself and does not return there; the subprogram's own M99 then returns.)
(expect: #100[fanuc]=5 #101[fanuc]=1 #102[fanuc]=vacant #100[haas]=vacant #101[haas]=2 #102[haas]=1 status=completed)
