(HEADER COMMENT)
#100=1 (SET ONE)
G90 G01 (MOVE) X1. F100 (FEED)
M30
(expect: motions=1 motion1=X1 status=completed)
