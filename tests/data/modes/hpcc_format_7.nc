(fivex: --preset head-bc --dialect syntec)
G05 P10000 X0 Y0 Z0 B0 C1.
(syn §3.1 COR-107 (iii): a rotary axis argument is not 0)
(expect: alarm=COR-107 alarm_line=2)
