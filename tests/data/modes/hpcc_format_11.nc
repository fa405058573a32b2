(fivex: --preset head-bc --dialect syntec)
G05 P10000 X0 Y0 Z0 B1. C-1.
(syn §3.1 COR-107 (vii): an axis argument is negative)
(expect: alarm=COR-107 alarm_line=2)
