O1
G90 G00 X0 Y0
M98 P2 L4
M30
O2
G68 X0 Y0 G91 R45.
G90 G01 X10. Y0 F100.
M99
(expect: motion3=X0~1e-6,Y10~1e-6 motion5=X-10~1e-6,Y0~1e-6 status=completed)
(skip: limits@7 line 7 runs four times in a row [M98 L4]: the corner between two of its runs is a junction, where the corner rule allows a speed step, that the check cannot tell from the line number)
