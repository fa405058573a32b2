(fivex: --preset head-bc --dialect syntec)
G05 P10000
G43.4 H1
(syn SYN-07/08/09, TV-16 [COR-140], decision: the other order - RTCP not started in HPCC)
(expect: alarm=COR-140 alarm_line=3)
