(fivex: --dialect haas --block-delete --optional-stop)
#100=#3030 (SINGLE BLOCK)
#101=#3031 (DRY RUN)
#102=#3032 (BLOCK DELETE)
#103=#3033 (OPTIONAL STOP)
/#104=1 (SKIPPED: BLOCK DELETE IS ON)
M30
(expect: #100=0 #101=0 #102=1 #103=1 #104=vacant status=completed)
