(fivex: --preset head-bc --dialect syntec)
G05 P0 X0
(decision: G05 P0 takes no axis argument - it would not move X)
(expect: alarm=COR-107 alarm_line=2)
