#3902=40
#100=#3902
#101=#3901
M30
(expect: #100=40 #101=0 status=completed)
