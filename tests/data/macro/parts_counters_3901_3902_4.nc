#100=1
(The end of the main program's text is not M30: no part counted.)
(expect: #3901=0 status=completed)
