(fivex: --preset head-bc --dialect syntec --allow-unbuilt)
G68.3 P0 X0 Y0 Z0
(expect: alarm=COR-141)
