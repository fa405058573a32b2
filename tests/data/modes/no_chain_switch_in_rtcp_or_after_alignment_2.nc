(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G68.2 X0 Y0 Z0 I0 J0 K0
G53.1
G10 L5000 P1
(expect: alarm=COR-160)
