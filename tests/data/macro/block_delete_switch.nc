/#100=1
#101=2
/G90 G00 X5.
M30
(The default is off.)
(expect: #100=1 status=completed)
