WHILE[1EQ2]DO1
#100=1
END1
#101=1
M30
(A false condition at once skips the body.)
(expect: #100=vacant status=completed)
