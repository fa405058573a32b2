#3901=5
M02
(expect: #3901=6 status=completed)
