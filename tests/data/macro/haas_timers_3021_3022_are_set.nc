(fivex: --dialect haas)
G04 P1.
#3021=10. (THE CYCLE START TIMER SET TO 10 S)
#3022=0.5 (THE FEED TIMER TO 0.5 S)
G90 G01 X50. F3000.
G04 P2.
#100=#3021
#101=#3022
#102=#3020
#103=#3023
M30
(Set, they count on from the value written: 10 + 1.05 [the feed] + 2 [the dwell] = 13.05 s)
(and 0.5 + 1.05 = 1.55 s. Power on and the present part are not changed by the writes:)
(1 + 1.05 + 2 = 4.05 s.)
(After M30 the part is complete: #3024 = 4.05 s, and the present part starts again.)
(expect: #100=13.05 #101=1.55 #102=4.05 #103=4.05 #3024=4.05 #3023=0 status=completed)
