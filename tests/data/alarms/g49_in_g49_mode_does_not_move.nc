G21 G17 G40 G49 G80 G90 G94
M30
(expect: motions=0)
