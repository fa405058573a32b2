G51 X0 Y0 I0 J1000
M30
(expect: alarm=PS0142)
