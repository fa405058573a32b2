(fivex: --dialect haas)
(The manual's sample O00098, inch: D01 holds a 5 mm tool radius here, 0.19685 in)
G20
T1 M06
G54 G00 G90 X0 Y0
G43 Z0.1 H01
S2000 M03
G12 I1.5 F10. Z-1.2 D01
G00 Z0.1
G55 X0 Y0
G12 I0.3 K1.5 Q0.3 F10. Z-1.2 D01
G00 Z0.1
G56 X0 Y0
G13 I1.5 F10. Z-1.2 D01
G00 Z0.1
G57 X0 Y0
G13 I0.3 K1.5 Q0.3 F10. Z-1.2 D01
G00 Z0.1
M30
(Each pocket plunges at the centre to Z-1.2 in = -30.48 mm and ends there. I alone is one)
(pass on 1.5 in less the tool radius: 38.1 - 5 = 33.1 mm; I0.3 K1.5 Q0.3 five passes on)
(0.3, 0.6, 0.9, 1.2, 1.5 in less 5 mm. Motions: G54 X0 Y0, the G43 Z move, G55-G57 X0 Y0)
(which do not move but are motions: 5, and 4 retracts; per I-only pocket 1 plunge + 3 arcs,)
(per I K Q pocket 1 + 2 x 5 + 1: 5 + 4 + 2 x 4 + 2 x 12 = 41. The tool ends at Z0.1 in = 2.54 mm;)
(M30 then cancels the tool length on a Haas, 96-8000 G49: the work Z is the nose's, 102.54.)
(expect: status=completed wX=0 wY=0 wZ=102.54 feeds=X0,Y0,Z-30.48/X0,Y0,Z-30.48/X0,Y0,Z-30.48/X0,Y0,Z-30.48 motions=41)
(skip: limits@8 the pocket's moves are one block: their corners, the plunge into the first half circle and the reversals between passes, take the planner's corner speed step, which the check allows only where the line changes)
(skip: limits@11 the pocket's moves are one block: their corners, the plunge into the first half circle and the reversals between passes, take the planner's corner speed step, which the check allows only where the line changes)
(skip: limits@14 the pocket's moves are one block: their corners, the plunge into the first half circle and the reversals between passes, take the planner's corner speed step, which the check allows only where the line changes)
(skip: limits@17 the pocket's moves are one block: their corners, the plunge into the first half circle and the reversals between passes, take the planner's corner speed step, which the check allows only where the line changes)
