#1=10.
#2=2
#3=3
G90 G01 F100 X#1 Y#[#2+1] Z-#1
X[#1*2] Y-[#2+1] Z#3
M30
(expect: motions=2 status=completed)
