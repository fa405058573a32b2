(A ( B) #100=3
M30
(The first `]` closes the comment: the assignment after it runs.)
(expect: #100=3 status=completed)
