(fivex: --preset head-bc --dialect syntec)
G05 P10000 E1.
(a positive E: its meaning is nowhere described, so not built - COR-100)
(expect: alarm=COR-100 alarm_line=2)
