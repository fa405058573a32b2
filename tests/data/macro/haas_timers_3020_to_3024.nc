(fivex: --dialect haas)
G04 P2. (2 S DWELL: OPERATING, NOT CUTTING)
G90 G01 X50. F3000. (REST TO REST 50 MM AT 50 MM/S)
G04 P0 (WAITS FOR THE MOTION: THE READS BELOW SEE IT)
#100=#3020
#101=#3021
#102=#3022
#103=#3023
#104=#3024
#105=#3025
G00 X100. (A RAPID: OPERATING, NOT CUTTING)
G04 P0
#106=#3022
M30
(The feed: L/v = 1 s plus the ramp 2 sqrt[v/J] = 0.05 s with J = 80000 mm/s3 [the mill3)
(preset, as tests/fixtures/exact_stop_g09_g61_g64.nc]: 1.05 s. Power on, cycle start and)
(present part: 2 + 1.05 = 3.05 s. Feed timer 1.05 s, before the rapid and after it. No part)
(complete yet when read: #3024 = #3025 = 0. After M30 the part is complete: #3024 is all of)
(its operating time, which the rapid lengthened, #3023 starts again at 0.)
(expect: #100=3.05 #101=3.05 #102=1.05 #103=3.05 #104=0 #105=0 #106=1.05 #3023=0 #3025=0 status=completed)
