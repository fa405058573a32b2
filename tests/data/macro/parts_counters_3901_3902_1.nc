M30
(expect: #3901=1 status=completed)
