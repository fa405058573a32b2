G53.3
(G53.3 exists only in the Syntec dialect.)
(expect: alarm=PS0010)
