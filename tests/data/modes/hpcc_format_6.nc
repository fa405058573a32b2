(fivex: --preset head-bc --dialect syntec)
G05 P10000 X0.5 Y0 Z0 B1. C1.
(syn §3.1 COR-107 (ii): a geometry axis argument is 0)
(expect: alarm=COR-107 alarm_line=2)
