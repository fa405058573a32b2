(fivex: --preset head-bc --dialect syntec)
G05 P10000
G43.4 H1 L1
(STCP not started in HPCC either)
(expect: alarm=COR-140 alarm_line=3)
