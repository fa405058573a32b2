G65 P9005 A1.
G65 P9005
M30
O9005
#[100+#100+1]=#2
#100=#100+1
#2=7.
M99
(expect: #100=2 #101=vacant #102=vacant status=completed)
