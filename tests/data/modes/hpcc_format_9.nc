(fivex: --preset head-bc --dialect syntec)
G05 P10000 B1. C1.
(syn §3.1 COR-107 (v): rotary axes given, no geometry axis)
(expect: alarm=COR-107 alarm_line=2)
