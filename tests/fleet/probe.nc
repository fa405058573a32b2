%
O1002 (FLEET: PROBE DOWN ONTO WHAT IS ON THE TABLE)
(tests/fleet/probe_block.json: a block whose top is at table Z-3 under X25 Y20; G54 = 0, so)
(on mill3 the table frame is the workpiece system. D1's ball, radius 5, touches the top with)
(its tip at Z-3: #101 = -3. Without the block the probe runs its whole move: #101 = -10.)
G90 G17 G21 G40 G49 G80
G10 L2 P1 X0. Y0. Z0.
G54 G00 X25. Y20.
G43 H1 D1 Z20.
G31 Z-10. F250.
#101=#5063
M30
%
