(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G68.2 X0 Y0 Z0 I0 J0 K0
G53.3 P-1
(syn SYN-22, TV-18 [Syntec only])
(expect: alarm=COR-149)
