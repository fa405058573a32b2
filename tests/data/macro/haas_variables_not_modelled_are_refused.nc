(fivex: --dialect haas)
#100=1
#101=#3028 (PALLETS LOADED ON THE RECEIVER: FIVEX HAS NO PALLET CHANGER)
M30
(expect: alarm=503 alarm_line=3 #100=1 #101=vacant)
