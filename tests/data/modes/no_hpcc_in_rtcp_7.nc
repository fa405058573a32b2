(fivex: --preset head-bc --dialect syntec)
G05 P10000
G43.5 H1
(expect: alarm=COR-140 alarm_line=3)
