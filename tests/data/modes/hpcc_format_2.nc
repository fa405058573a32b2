(fivex: --preset head-bc --dialect syntec)
G05
(syn §3.1 COR-107 (i): G05 without P)
(expect: alarm=COR-107 alarm_line=2)
