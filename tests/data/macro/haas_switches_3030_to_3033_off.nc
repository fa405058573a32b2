(fivex: --dialect haas)
#100=#3030
#101=#3031
#102=#3032
#103=#3033
/#104=1 (RUN: BLOCK DELETE IS OFF)
M30
(expect: #100=0 #101=0 #102=0 #103=0 #104=1 status=completed)
