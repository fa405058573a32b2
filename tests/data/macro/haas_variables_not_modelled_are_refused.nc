(fivex: --dialect haas)
#100=1
#101=#3021 (CYCLE START TIMER: NOT MODELLED)
M30
(expect: alarm=503 alarm_line=3 #100=1 #101=vacant)
