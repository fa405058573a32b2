G17 G90 G16
G81 X100. Y30. Z-20. R-5. F200.
Y150.
Y270.
G15 G80
M30
(Four motions a hole: position, R, bottom, initial level.)
(expect: motions=12 motion1=X86.60254037844386~1e-6,Y50~1e-6 motion5=X-86.60254037844386~1e-6,Y50~1e-6 motion9=X0~1e-6,Y-100~1e-6 status=completed)
