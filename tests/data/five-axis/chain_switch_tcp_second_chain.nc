(fivex: --machine ../../../machines/head-exchange-bc-ac.json --dialect syntec)
N1 G90 G54 G00 X0. Y0. Z200. A0. B0. C0.
N2 G10 L5000 P2
N3 G43.4 H1
N4 G01 X0. Y0. Z0. A90. C0. F2000.
N5 M30
(Syntec G10 L5000 P2 on the exchangeable-head machine: set 2 is the A/C head, its pivot 150 above the carriage point, its nose 50 below it. The workpiece origin is the nose, 50 below the carriage point: at N3 G43.4 puts the 100 mm tool's tip on the programmed Z200, so the carriage rises to 200 + 100 = 300 (tip in machine Z 300 - 50 - 100 = 150); N4 keeps the tip on the Z line down to 0 while A turns to 90: A turns +90 about +X, carrying the tip's -300 from the pivot along Z to +300 along Y, so the tip is 300 in Y and 150 in Z from the carriage point. For the tip at the workpiece origin, machine 0, 0, -50, the carriage stands at 0, -300, -200. Set 1's B/C head would put the same axes' tip elsewhere; the tip invariant reads every sample through set 2.)
(expect: status=completed wX=0 wY=0 wZ=0 mX=0 mY=-300 mZ=-200 mA=90 mB=0 mC=0)
