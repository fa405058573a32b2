(fivex: --preset mill3 --dialect syntec --allow-unbuilt)
G41 D1
G68.2 X0 Y0 Z0 I0 J0 K0
G53.6 H1
(syn SYN-21, TV-20 [Syntec only])
(expect: alarm=MAR-406)
