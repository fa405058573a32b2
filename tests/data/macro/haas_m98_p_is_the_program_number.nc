(fivex: --dialect fanuc,haas)
M98 P30010
M30
O0010
#100=[#100+1]
M99
O30010
#101=1
M99
(FANUC reads P30010 as O0010 three times; Haas as O30010 once.)
(expect: #100[fanuc]=3 #101[fanuc]=vacant #100[haas]=vacant #101[haas]=1 status=completed)
