(fivex: --preset head-bc --allow-unbuilt)
G43.5 H1
G01 X10. I0 J0 K0 F100
G49
M30
(syn SYN-08, TV-12, TV-13/13b [Syntec only])
(expect: status=completed)
