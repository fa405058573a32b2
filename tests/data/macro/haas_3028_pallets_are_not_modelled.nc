(fivex: --dialect haas)
#100=#3028 (NUMBER OF THE PALLET LOADED ON THE RECEIVER)
M30
(expect: alarm=503 alarm_line=2 #100=vacant)
