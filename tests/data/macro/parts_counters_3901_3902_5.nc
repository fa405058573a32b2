#3902=40
#100=#3902
#101=#3901
M30
(expect: #3902=40 status=completed)
