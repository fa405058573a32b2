#3901=5
M30
(expect: #3901=6 status=completed)
