(fivex: --preset head-bc --dialect syntec)
G05 P10000 E-1.
(syn §3.1 COR-107 (ii): G05 E is positive)
(expect: alarm=COR-107 alarm_line=2)
