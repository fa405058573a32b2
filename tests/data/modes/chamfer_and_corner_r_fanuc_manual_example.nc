(fivex: --dialect fanuc,haas)
G90 G21 G54 G00 X0 Y0 Z0
N002 G00 X10.0 Y10.0
N003 G01 X50.0 F10.0 ,C5.0
N004 Y25.0 ,R8.0
N005 G03 X80.0 Y55.0 R30.0 ,R8.0
N006 G01 X50.0 ,R8.0
N007 Y70.0 ,C5.0
N008 X10.0 ,C5.0
N009 Y10.0
N010 G00 X0 Y0
M30
(The manual's example of chamfering and corner R [FANUC 0i-M "Chamfering and corner R", as)
(reproduced at en.cncforum.net/t/cnc-milling-c-and-r-codes-chamfering-and-corner/267, there with)
(C and R without the comma]; its G92 X0 Y0 is the work zero here. By hand:)
(N003: corner X50 Y10, C5: X45 Y10 to X50 Y15. N005's arc from X50 Y25 to X80 Y55, R30 counter-)
(clockwise: centre X50 Y55 [the chord's left], so it leaves X50 Y25 along +X: N004 [+Y] turns)
(right by 90 degrees into it. R8 on the right: 8 right of the line [x = 58] and 8 outside the)
(circle [38 from X50 Y55]: y = 55 - sqrt[38^2 - 8^2] = 17.851648757987; the line stops at X50)
(Y17.851649, the fillet [clockwise] touches the arc at X50 + 30*8/38 = 56.315789473684,)
(Y55 - 30*37.148351/38 = 25.672354282621. N005 ends at X80 Y55 going +Y; N006 runs -X: a left)
(turn, R8 on the left: inside the circle [22 from the centre] and 8 below the line [y = 47]:)
(x = 50 + sqrt[22^2 - 8^2] = 70.493901531919; the arc stops at X50 + 30*20.493902/22 =)
(77.946229361708, Y55 - 30*8/22 = 44.090909090909, the fillet [counter-clockwise] ends at)
(X70.493902 Y55. N006's corner X50 Y55 to +Y, R8, 90 degrees right: X58 Y55 to X50 Y63.)
(N007 corner X50 Y70, C5: X50 Y65 to X45 Y70. N008 corner X10 Y70, C5: X15 Y70 to X10 Y65.)
(expect: feeds=X45,Y10/X50,Y15/X50,Y17.851648757987~1e-9/X58,Y55/X50,Y65/X45,Y70/X15,Y70/X10,Y65/X10,Y10)
(expect: motion6=X56.315789473684~1e-9,Y25.672354282621~1e-9 motion7=X77.946229361708~1e-9,Y44.090909090909~1e-9)
(expect: motion8=X70.493901531919~1e-9,Y55 motion10=X50,Y63 motions=16 status=completed)
