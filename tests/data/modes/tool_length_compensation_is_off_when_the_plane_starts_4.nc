(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G68.2 X0 Y0 Z0 I0 J0 K0
G53.1
G43 H1
G68.2 X1. Y0 Z0 I0 J0 K0
(expect: alarm=COR-100)
