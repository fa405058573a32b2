(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G43.5 H1
G01 X10. I0 F100
(syn SYN-08, TV-12, TV-13/13b [Syntec only])
(expect: alarm=COR-159)
