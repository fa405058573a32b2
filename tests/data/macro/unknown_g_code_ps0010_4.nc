G53.3
M30
(A code of the other dialect: G53.3 is Syntec's.)
(expect: alarm=PS0010)
